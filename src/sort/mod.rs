//! Visibility ordering of tets for a viewpoint: centroid (approximate), MPVO and K-D exact.

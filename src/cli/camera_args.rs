//! Camera options shared by every command that takes a view (explicit, ParaView-style, .pvcc).

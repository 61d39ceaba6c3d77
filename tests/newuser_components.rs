//! One component of a vector, as ParaView's "Color By" menu offers it (X, Y, Z, Magnitude) and
//! its CSV export names it (`v:0`): `--scalar v:X` was "no such array", so only the magnitude
//! could be drawn. Fixture: fixtures/newuser/make_vector_field.py (`v` is the point's
//! coordinates, so `v:X` must draw exactly what `coord:x` draws).

mod common;

use common::{fixture, tempdir, tetkit};

#[test]
fn a_vector_component_draws_like_the_coordinate_it_holds() -> Result<(), Box<dyn std::error::Error>>
{
    let dir = tempdir();
    let input = fixture("newuser/vector_field.vtu");
    let draw = |scalar: &str, png: &str| {
        let out = dir.path().join(png);
        let r = tetkit([
            "render",
            input.to_str().unwrap_or(""),
            "-o",
            out.to_str().unwrap_or(""),
            "--size",
            "32x32",
            "--azimuth",
            "30",
            "--elevation",
            "20",
            "--scalar",
            scalar,
            "-q",
        ]);
        (r, out)
    };
    for (comp, axis) in [
        ("v:X", "coord:x"),
        ("v:1", "coord:y"),
        ("point:v:Z", "coord:z"),
    ] {
        let (a, pa) = draw(comp, "a.png");
        a.assert_success();
        let (b, pb) = draw(axis, "b.png");
        b.assert_success();
        assert_eq!(std::fs::read(&pa)?, std::fs::read(&pb)?, "{comp} vs {axis}");
    }
    let (m, pm) = draw("v:Magnitude", "m.png");
    m.assert_success();
    let (p, pp) = draw("v", "p.png");
    p.assert_success();
    assert_eq!(std::fs::read(&pm)?, std::fs::read(&pp)?);
    let out = dir.path().join("bad.png");
    let (r, _) = draw("v:W", "bad.png");
    r.assert_failure(&["vector_field.vtu", "v:W", "'W' is not a component of 'v'"]);
    assert!(!out.exists());
    let (r, _) = draw("v:3", "bad.png");
    r.assert_failure(&["v:3", "3 component(s)"]);
    assert!(!out.exists());
    Ok(())
}

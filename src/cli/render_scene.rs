//! `tetkit render --scene` with bodies: the scene's camera under the command line's, then PT or
//! the ray caster with per-pixel body crossings, and the region-code report.

use anyhow::Result;
use std::time::Instant;

use super::camera_args::CameraArgs;
use super::render::{
    frame_path, orbit_camera, order_for, MethodChoice, Progress, RenderArgs, Session, SortChoice,
};
use crate::camera::Camera;
use crate::render::cut::{self, RegionReport, SceneLook, ShaderCache};
use crate::render::pt::View;
use crate::scene::Scene;

/// The command line's camera options with the scene's filling what they leave unset (so every
/// option given on the command line wins; `--perspective` turns off a scene's `parallel = true`).
pub fn camera_args(cli: &CameraArgs, scene: &Scene) -> CameraArgs {
    let c = &scene.camera;
    let mut a = cli.clone();
    a.position = a.position.or(c.position);
    a.focal = a.focal.or(c.focal);
    a.up = a.up.or(c.up);
    a.view_angle = a.view_angle.or(c.view_angle);
    a.parallel = !a.perspective && (a.parallel || c.parallel == Some(true));
    a.parallel_scale = a.parallel_scale.or(c.parallel_scale);
    a
}

#[derive(serde::Serialize)]
struct FrameReport {
    frame: usize,
    seconds: f64,
    regions: RegionReport,
}

pub fn run(
    args: &RenderArgs,
    session: &Session,
    scene: &Scene,
    cam0: Camera,
    step: super::render::Orbit,
    mut progress: Progress,
) -> Result<()> {
    let look = &args.look;
    let frames = args.orbit.unwrap_or(1);
    let (w, h) = look.size;
    let t_setup = Instant::now();
    let mut sl = SceneLook::new(scene, &session.tf, &session.base)?;
    sl.culling = !args.no_culling;
    let mut summary = vec![format!(
        "{} tets, array '{}', read {:.3} s; scene {}: {} bodies, rule {:?}, culling {}",
        session.mesh.tets.len(),
        session.field_name,
        session.read_s,
        scene.file.display(),
        scene.bodies.len(),
        scene.rule,
        if sl.culling { "on" } else { "off" }
    )];
    let mut reports = Vec::new();
    match args.method {
        MethodChoice::Pt => {
            let sorter = match args.sort {
                SortChoice::None => None,
                _ => Some(session.sorter()?),
            };
            // The default's table is what the plain path would build; bodies' are built when a
            // frame first needs them.
            let mut cache = ShaderCache::new(args.integration, session.table, session.lmax)
                .with_default(crate::render::prepare::shader(
                    &session.tf,
                    args.integration,
                    session.table,
                    session.lmax,
                ));
            summary.push(format!(
                "setup (adjacency, leaves, default table) {:.3} s",
                t_setup.elapsed().as_secs_f64()
            ));
            progress.step("setup");
            for i in 0..frames {
                let cam = orbit_camera(&cam0, &step, i);
                let t = Instant::now();
                let (order, sort_s) =
                    order_for(sorter.as_ref(), session.mesh.tets.len(), &cam, args.sort);
                let built = cache.build_s;
                let (img, stats, rep) = cut::pt_render(
                    &View::new(&cam, w, h),
                    &cam,
                    &session.mesh.points,
                    &session.mesh.tets,
                    &session.field,
                    &order,
                    &sl,
                    &mut cache,
                );
                let frame_s = t.elapsed().as_secs_f64();
                img.write_png(&frame_path(&args.output, i, frames), look.background)?;
                summary.push(format!(
                    "frame {i}: {frame_s:.3} s (sort {sort_s:.3}, tables {:.3}); codes {:?} -> {} drawn classes, {} tables; pixels with crossings {}, fragments {} ({} split into {} pieces)",
                    cache.build_s - built,
                    rep.codes,
                    rep.drawn_classes,
                    rep.tables,
                    rep.pixels_with_crossings,
                    stats.fragments,
                    rep.split_fragments,
                    rep.pieces
                ));
                reports.push(FrameReport {
                    frame: i,
                    seconds: frame_s,
                    regions: rep,
                });
                progress.step("frame");
            }
        }
        MethodChoice::Raycast => {
            // The bodies' ray caster integrates every piece exactly; a table lookup asked for
            // would be silently ignored otherwise.
            if args.ray_integration == super::render::RayIntegration::Preintegrated {
                anyhow::bail!(
                    "{}: --ray-integration preintegrated is not supported with a scene's bodies (the ray caster integrates each body's pieces exactly); leave it out, or use --method pt",
                    scene.file.display()
                );
            }
            let topo = session.topology();
            let rc = session.raycaster(&topo);
            summary.push(format!(
                "setup (adjacency, grids) {:.3} s",
                t_setup.elapsed().as_secs_f64()
            ));
            progress.step("setup");
            for i in 0..frames {
                let cam = orbit_camera(&cam0, &step, i);
                let t = Instant::now();
                let (img, st, rep) = cut::raycast(&rc, &sl, &cam, w, h);
                let frame_s = t.elapsed().as_secs_f64();
                img.write_png(&frame_path(&args.output, i, frames), look.background)?;
                summary.push(format!(
                    "frame {i}: {frame_s:.3} s; codes {:?} -> {} drawn classes; segments {}, re-entries {}, lost walks {}; pixels with crossings {}, segments split {} into {} pieces",
                    rep.codes,
                    rep.drawn_classes,
                    st.segments,
                    st.reentries,
                    st.lost,
                    rep.pixels_with_crossings,
                    rep.split_fragments,
                    rep.pieces
                ));
                reports.push(FrameReport {
                    frame: i,
                    seconds: frame_s,
                    regions: rep,
                });
                progress.step("frame");
            }
        }
    }
    progress.finish_with(look.quiet, summary);
    if args.json {
        let bodies: Vec<serde_json::Value> = scene
            .bodies
            .iter()
            .enumerate()
            .map(|(i, b)| {
                serde_json::json!({
                    "bit": i,
                    "name": b.name,
                    "line": b.line,
                    "action": match b.action {
                        crate::scene::Action::Cut => "cut",
                        crate::scene::Action::Transfer(_) => "transfer",
                    },
                })
            })
            .collect();
        let report = serde_json::json!({
            "tets": session.mesh.tets.len(),
            "bodies": bodies,
            "rule": format!("{:?}", scene.rule).to_lowercase(),
            "culling": sl.culling,
            "frames": reports,
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Aabb;
    use std::path::Path;

    #[test]
    fn perspective_overrides_a_parallel_scene() {
        let s = crate::scene::parse(
            "[camera]\nparallel = true\nparallel_scale = 0.5\n",
            Path::new("s.toml"),
        )
        .unwrap();
        let bounds = Aabb {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let from_scene = camera_args(&CameraArgs::default(), &s)
            .camera(&bounds)
            .unwrap();
        assert!(from_scene.parallel);
        assert_eq!(from_scene.parallel_scale, 0.5);
        let cli = CameraArgs {
            perspective: true,
            ..CameraArgs::default()
        };
        let persp = camera_args(&cli, &s).camera(&bounds).unwrap();
        assert!(!persp.parallel);
        // A plain scene stays perspective unless --parallel asks.
        let plain = crate::scene::parse("", Path::new("s.toml")).unwrap();
        assert!(
            !camera_args(&CameraArgs::default(), &plain)
                .camera(&bounds)
                .unwrap()
                .parallel
        );
        let par = CameraArgs {
            parallel: true,
            ..CameraArgs::default()
        };
        assert!(camera_args(&par, &plain).camera(&bounds).unwrap().parallel);
    }
}

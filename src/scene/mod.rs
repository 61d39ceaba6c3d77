//! Scenes: cutting bodies and per-region transfer functions (seed 003, Yang et al. 2002), exact
//! per-pixel region codes along rays, region-code merging, and tet classification.
//!
//! A sample's region code has bit `i` set when body `i` (in file order) contains it. The scene's
//! [`Rule`] maps every code to an [`Effect`]: drawn with the default transfer function, cut (not
//! drawn), or drawn with one body's transfer function.

pub mod classify;
mod exact;
mod fb;
mod file;
pub mod frustum;
mod interval;
pub mod merge;
pub mod ray;
pub mod shapes;
pub mod surface;

use std::path::{Path, PathBuf};

use crate::camera::Camera;
use crate::geom::Aabb;
pub use file::{load, parse};
pub use shapes::Primitive;
pub use surface::TriSurface;

/// At most 8 bodies: a region code is one byte, as the paper's 8-bit stencil.
pub const MAX_BODIES: usize = 8;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// The scene file, for messages.
    pub file: PathBuf,
    pub camera: CameraSpec,
    /// The transfer function outside every body (also where no body's effect applies).
    pub transfer: Option<TransferSpec>,
    pub rule: Rule,
    pub bodies: Vec<Body>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    pub name: String,
    pub shape: Shape,
    pub action: Action,
    /// The 1-based line of the body's `[[body]]` table in the scene file.
    pub line: usize,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Primitive(Primitive),
    Surface(Box<TriSurface>),
}

/// What a body does to the samples it contains.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Inside is not drawn.
    Cut,
    /// Inside is drawn with this transfer function.
    Transfer(TransferSpec),
}

/// How overlapping bodies combine (the paper's set operations between the bodies' sets).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Rule {
    /// The first body in file order that contains a sample decides.
    #[default]
    Precedence,
    /// A sample in any body is cut if any of its bodies cuts, else drawn with the transfer
    /// function of its first body: the union of the cut bodies is removed.
    Union,
    /// Only samples inside every body get the first body's action; elsewhere the default.
    Intersection,
    /// The first body minus all the others: samples in the first body and in no other get its
    /// action; everything else the default.
    Difference,
}

/// What applies to a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Effect {
    /// The scene's default transfer function.
    Default,
    /// Not drawn.
    Cut,
    /// Drawn with body `i`'s transfer function.
    Transfer(usize),
}

/// A transfer function as plain data; the renderer builds its tables from it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TransferSpec {
    /// A colormap name (as `tetkit render --colormap` takes).
    pub colormap: Option<String>,
    /// A preset file (ParaView colormap JSON), resolved against the scene file's folder.
    pub preset: Option<PathBuf>,
    /// `(scalar, opacity)` points with non-decreasing scalars; a repeated scalar makes a step,
    /// e.g. the paper's two-level `[[0,0.07],[T,0.07],[T,0.93],[1,0.93]]`.
    pub opacity: Vec<[f64; 2]>,
    /// The scalar range the colormap spans; `None`: the data's range.
    pub range: Option<[f64; 2]>,
    /// The length over which an opacity is reached (ParaView's scalar opacity unit distance).
    pub unit_distance: Option<f64>,
}

impl TransferSpec {
    /// Maps its scalars (range and opacity points) to `(s - offset) * scale`, as the render
    /// does to the field (see `render::field::scalar_offset` and `scalar_scale`).
    pub fn shift_scalars(&mut self, offset: f64, scale: f64) {
        if let Some(r) = self.range.as_mut() {
            *r = r.map(|x| (x - offset) * scale);
        }
        for p in &mut self.opacity {
            p[0] = (p[0] - offset) * scale;
        }
    }
}

impl Scene {
    /// Maps the scalars of every transfer function the scene declares to `(s - offset) * scale`.
    pub fn shift_scalars(&mut self, offset: f64, scale: f64) {
        if let Some(t) = self.transfer.as_mut() {
            t.shift_scalars(offset, scale);
        }
        for b in &mut self.bodies {
            if let Action::Transfer(t) = &mut b.action {
                t.shift_scalars(offset, scale);
            }
        }
    }
}

/// Camera settings a scene may fix; unset fields keep the command line's or the default view.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraSpec {
    pub position: Option<[f64; 3]>,
    pub focal: Option<[f64; 3]>,
    pub up: Option<[f64; 3]>,
    pub view_angle: Option<f64>,
    pub parallel: Option<bool>,
    pub parallel_scale: Option<f64>,
}

impl CameraSpec {
    pub fn is_empty(&self) -> bool {
        *self == CameraSpec::default()
    }

    /// Overrides the fields the scene sets.
    pub fn apply(&self, cam: &mut Camera) {
        if let Some(p) = self.position {
            cam.position = p;
        }
        if let Some(f) = self.focal {
            cam.focal = f;
        }
        if let Some(u) = self.up {
            cam.up = u;
        }
        if let Some(a) = self.view_angle {
            cam.view_angle = a;
        }
        if let Some(p) = self.parallel {
            cam.parallel = p;
        }
        if let Some(s) = self.parallel_scale {
            cam.parallel_scale = s;
        }
    }
}

impl Body {
    pub fn bounds(&self) -> Aabb {
        match &self.shape {
            Shape::Primitive(p) => p.bounds(),
            Shape::Surface(s) => s.bounds,
        }
    }

    /// Whether the closed body contains `p` (surfaces: ray parity, exact).
    pub fn contains(&self, p: &[f64; 3]) -> bool {
        match &self.shape {
            Shape::Primitive(s) => s.contains(p),
            Shape::Surface(s) => s.contains(p),
        }
    }

    /// Depths `t >= 0` where the ray `o + t d` crosses the body's surface, unsorted. Their
    /// count's parity says whether `o` is inside (the line leaves every body eventually).
    pub fn crossings(&self, o: &[f64; 3], d: &[f64; 3], out: &mut Vec<f64>) {
        match &self.shape {
            Shape::Primitive(s) => {
                if let Some((t0, t1)) = s.line_span(o, d) {
                    if t0 < t1 {
                        for t in [t0, t1] {
                            if t >= 0.0 {
                                out.push(t);
                            }
                        }
                    }
                }
            }
            Shape::Surface(s) => s.crossings(o, d, out),
        }
    }
}

impl Scene {
    /// A scene with no bodies, as an empty file gives.
    pub fn empty(file: &Path) -> Scene {
        Scene {
            file: file.to_path_buf(),
            ..Scene::default()
        }
    }

    pub fn full_mask(&self) -> u8 {
        if self.bodies.len() >= 8 {
            0xff
        } else {
            ((1u16 << self.bodies.len()) - 1) as u8
        }
    }

    /// What applies to a sample with region code `code`.
    pub fn effect(&self, code: u8) -> Effect {
        let act = |i: usize| match &self.bodies[i].action {
            Action::Cut => Effect::Cut,
            Action::Transfer(_) => Effect::Transfer(i),
        };
        let code = code & self.full_mask();
        if code == 0 || self.bodies.is_empty() {
            return Effect::Default;
        }
        let first = code.trailing_zeros() as usize;
        match self.rule {
            Rule::Precedence => act(first),
            Rule::Union => {
                let any_cut = (0..self.bodies.len())
                    .any(|i| code >> i & 1 == 1 && self.bodies[i].action == Action::Cut);
                if any_cut {
                    Effect::Cut
                } else {
                    act(first)
                }
            }
            Rule::Intersection => {
                if code == self.full_mask() {
                    act(0)
                } else {
                    Effect::Default
                }
            }
            Rule::Difference => {
                if code == 1 {
                    act(0)
                } else {
                    Effect::Default
                }
            }
        }
    }

    /// The transfer function of an effect (`None` for a cut or a default the scene leaves to the
    /// command line).
    pub fn transfer_of(&self, e: Effect) -> Option<&TransferSpec> {
        match e {
            Effect::Default => self.transfer.as_ref(),
            Effect::Cut => None,
            Effect::Transfer(i) => match &self.bodies[i].action {
                Action::Transfer(t) => Some(t),
                Action::Cut => None,
            },
        }
    }
}

/// A code as a bit string, body 0 rightmost (as the paper writes stencil values).
pub fn code_string(code: u8, bits: usize) -> String {
    (0..bits.max(1))
        .rev()
        .map(|i| if code >> i & 1 == 1 { '1' } else { '0' })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene_with(actions: &[bool], rule: Rule) -> Scene {
        Scene {
            rule,
            bodies: actions
                .iter()
                .enumerate()
                .map(|(i, &cut)| Body {
                    name: format!("b{i}"),
                    shape: Shape::Primitive(Primitive::Sphere {
                        center: [0.0; 3],
                        radius: 1.0,
                    }),
                    action: if cut {
                        Action::Cut
                    } else {
                        Action::Transfer(TransferSpec::default())
                    },
                    line: 1,
                })
                .collect(),
            ..Scene::default()
        }
    }

    #[test]
    fn rules_map_codes_to_effects() {
        // Body 0 cuts, body 1 carries a transfer function (the paper's figure 10).
        let s = scene_with(&[true, false], Rule::Precedence);
        assert_eq!(s.effect(0b00), Effect::Default);
        assert_eq!(s.effect(0b01), Effect::Cut);
        assert_eq!(s.effect(0b10), Effect::Transfer(1));
        assert_eq!(s.effect(0b11), Effect::Cut);
        let s = scene_with(&[false, true], Rule::Precedence);
        assert_eq!(s.effect(0b11), Effect::Transfer(0));
        let s = scene_with(&[false, true], Rule::Union);
        assert_eq!(s.effect(0b11), Effect::Cut);
        assert_eq!(s.effect(0b01), Effect::Transfer(0));
        let s = scene_with(&[false, true], Rule::Intersection);
        assert_eq!(s.effect(0b01), Effect::Default);
        assert_eq!(s.effect(0b11), Effect::Transfer(0));
        let s = scene_with(&[false, true], Rule::Difference);
        assert_eq!(s.effect(0b01), Effect::Transfer(0));
        assert_eq!(s.effect(0b11), Effect::Default);
        assert_eq!(s.effect(0b10), Effect::Default);
        assert_eq!(code_string(0b010, 3), "010");
    }
}

// Projected tetrahedra, stage 3: rasterize the fan triangles and shade each fragment from its
// (Sf, Sb, l), recovered from the homogeneous per-vertex attributes written by classify.wgsl.
// Blending (set on the pipeline) is premultiplied 'over' in front-to-back order:
// dst = dst + (1 - dst.a) src, the CPU path's compositing step.

struct Shade {
    // mode (0 average, 1 linear, 2 preintegrated), nodes per function or table scalar count,
    // table length count, unused
    mode: vec4<u32>,
}

@group(0) @binding(0) var<uniform> fr: Frame;
@group(0) @binding(1) var<uniform> sh: Shade;
// Pre-integration tables, stacked along z: x = Sf, y = Sb, z = l + table * nl.
@group(0) @binding(2) var table: texture_3d<f32>;
// Transfer-function nodes (r, g, b, extinction), stacked per function.
@group(0) @binding(3) var<storage, read> nodes: array<vec4<f32>>;
// Per stacked function: scalar origin, 1 / scalar step, 1 / length step, last node index.
@group(0) @binding(4) var<storage, read> luts: array<vec4<f32>>;
// Scenes only. Layer 0: (crossing count, start code); layer i: (view depth, code after it).
@group(0) @binding(5) var crossings: texture_2d_array<f32>;
// Scenes only: stacked function of each region code, or 0xffffffff where it is cut.
@group(0) @binding(6) var<storage, read> slots: array<u32>;

const CUT: u32 = 0xffffffffu;

struct VOut {
    @builtin(position) pos: vec4<f32>,
    @location(0) @interpolate(linear) h: vec4<f32>,
}

@vertex
fn vs(@location(0) p: vec2<f32>, @location(1) h: vec4<f32>) -> VOut {
    var o: VOut;
    o.pos = vec4<f32>(p, 0.5, 1.0);
    o.h = h;
    return o;
}

fn tf_eval(s: f32, k: u32) -> vec4<f32> {
    let lut = luts[k];
    let x = clamp((s - lut.x) * lut.y, 0.0, lut.w);
    let n = sh.mode.y;
    let i = min(u32(x), n - 2u);
    let t = x - f32(i);
    let a = nodes[k * n + i];
    let b = nodes[k * n + i + 1u];
    return a + t * (b - a);
}

fn average(sf: f32, sb: f32, l: f32, k: u32) -> vec4<f32> {
    let a = tf_eval(sf, k);
    let b = tf_eval(sb, k);
    let alpha = 1.0 - exp(-0.5 * (a.w + b.w) * l);
    let h = 0.5 * alpha;
    return vec4<f32>((a.xyz + b.xyz) * h, alpha);
}

// int_0^1 exp(-(p u + q u^2)) du by composite 4-point Gauss-Legendre on pieces of optical depth
// <= 0.5, stopping where the depth passes 40 (as integrate::depth_integral, in f32).
fn depth_integral(p: f32, q: f32) -> f32 {
    let t1 = p + q;
    if (!(t1 > 1e-30)) {
        return 1.0;
    }
    var umax = 1.0;
    if (t1 > 40.0) {
        let disc = max(p * p + 160.0 * q, 0.0);
        umax = clamp(80.0 / (p + sqrt(disc)), 0.0, 1.0);
    }
    let slope = max(max(p, p + 2.0 * q * umax), 0.0);
    let m = u32(clamp(ceil(slope * umax / 0.5), 1.0, 400.0));
    let hh = umax / f32(m);
    let gx = vec4<f32>(0.06943184420297371, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263);
    let gw = vec4<f32>(0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269);
    var sum = 0.0;
    for (var k = 0u; k < m; k++) {
        let a = f32(k) * hh;
        let u = a + gx * hh;
        sum += dot(gw, exp(-(u * (p + q * u))));
    }
    return sum * hh;
}

fn linear(sf: f32, sb: f32, l: f32, k: u32) -> vec4<f32> {
    let a = tf_eval(sf, k);
    let b = tf_eval(sb, k);
    let p = l * a.w;
    let q = 0.5 * l * (b.w - a.w);
    let trans = exp(-(p + q));
    var i = 0.0;
    if (any(a.xyz != b.xyz)) {
        i = depth_integral(p, q);
    }
    return vec4<f32>(a.xyz - b.xyz * trans + (b.xyz - a.xyz) * i, 1.0 - trans);
}

// A fragment of any length (PreintTable::segment): past the table's length axis, the
// front-to-back composite of equal pieces within it.
fn preintegrated(sf: f32, sb: f32, l: f32, k: u32) -> vec4<f32> {
    let top = f32(sh.mode.z - 1u);
    let x = l * luts[k].z;
    if (!(x > top)) {
        return table_lookup(sf, sb, l, k);
    }
    let n = min(ceil(x / top), 65536.0);
    let dl = l / n;
    let ds = (sb - sf) / n;
    var acc = vec4<f32>(0.0);
    for (var i = 0u; i < u32(n); i++) {
        let a = sf + ds * f32(i);
        let c = table_lookup(a, a + ds, dl, k);
        acc += (1.0 - acc.w) * c;
    }
    return acc;
}

// Trilinear lookup with the CPU table's index arithmetic (PreintTable::lookup).
fn table_lookup(sf: f32, sb: f32, l: f32, k: u32) -> vec4<f32> {
    let lut = luts[k];
    let ns = sh.mode.y;
    let nl = sh.mode.z;
    let top = f32(ns - 1u);
    let xf = clamp((sf - lut.x) * lut.y, 0.0, top);
    let xb = clamp((sb - lut.x) * lut.y, 0.0, top);
    let xl = clamp(l * lut.z, 0.0, f32(nl - 1u));
    let i = min(u32(xf), ns - 2u);
    let j = min(u32(xb), ns - 2u);
    let kl = min(u32(xl), nl - 2u);
    let tf = xf - f32(i);
    let tb = xb - f32(j);
    let tl = xl - f32(kl);
    var pl: array<vec4<f32>, 2>;
    for (var dz = 0u; dz < 2u; dz++) {
        let z = i32(k * nl + kl + dz);
        let c00 = textureLoad(table, vec3<i32>(i32(i), i32(j), z), 0);
        let c10 = textureLoad(table, vec3<i32>(i32(i + 1u), i32(j), z), 0);
        let c01 = textureLoad(table, vec3<i32>(i32(i), i32(j + 1u), z), 0);
        let c11 = textureLoad(table, vec3<i32>(i32(i + 1u), i32(j + 1u), z), 0);
        let r0 = c00 + tf * (c10 - c00);
        let r1 = c01 + tf * (c11 - c01);
        pl[dz] = r0 + tb * (r1 - r0);
    }
    return pl[0] + tl * (pl[1] - pl[0]);
}

fn shade(sf: f32, sb: f32, l: f32, k: u32) -> vec4<f32> {
    if (sh.mode.x == 0u) {
        return average(sf, sb, l, k);
    } else if (sh.mode.x == 1u) {
        return linear(sf, sb, l, k);
    }
    return preintegrated(sf, sb, l, k);
}

// A fragment's entry and exit view depths, scalars and the world length per unit of depth.
struct Span {
    zf: f32,
    zb: f32,
    sf: f32,
    sb: f32,
    stretch: f32,
}

fn span(in: VOut) -> Span {
    let h = in.h;
    var o: Span;
    o.stretch = 1.0;
    if (fr.flags.y != 0u) {
        o.zf = h.x;
        o.sf = h.y;
        o.zb = h.z;
        o.sb = h.w;
    } else {
        o.zf = 1.0 / h.x;
        o.sf = h.y * o.zf;
        o.zb = 1.0 / h.z;
        o.sb = h.w * o.zb;
        let xs = (2.0 * in.pos.x / fr.size.x - 1.0) * fr.size.w;
        let ys = 1.0 - 2.0 * in.pos.y / fr.size.y;
        let a = fr.size.z * xs;
        let b = fr.size.z * ys;
        o.stretch = sqrt(1.0 + a * a + b * b);
    }
    return o;
}

@fragment
fn fs(in: VOut) -> @location(0) vec4<f32> {
    let sp = span(in);
    var l = max((sp.zb - sp.zf) * sp.stretch, 0.0);
    if (!(l <= 3.4e38)) {
        l = 0.0;
    }
    return shade(sp.sf, sp.sb, l, 0u);
}

// With scene bodies: the fragment's segment is split where the pixel's ray crosses a body, each
// piece shaded with its region's function (nothing where cut) and the pieces composited front to
// back; a crossing between codes of one function splits nothing (as render::cut).
@fragment
fn fs_scene(in: VOut) -> @location(0) vec4<f32> {
    let sp = span(in);
    let zf = sp.zf;
    let zb = sp.zb;
    if (!(zb > zf) || !(abs(zf) <= 3.4e38) || !(abs(zb) <= 3.4e38)) {
        return vec4<f32>(0.0);
    }
    let p = vec2<i32>(in.pos.xy);
    let head = textureLoad(crossings, p, 0, 0).xy;
    let n = i32(head.x);
    var code = u32(head.y);
    var i = 1;
    while (i <= n) {
        let c = textureLoad(crossings, p, i, 0).xy;
        if (!(c.x <= zf)) {
            break;
        }
        code = u32(c.y);
        i++;
    }
    var cur = slots[code];
    var a = zf;
    var acc = vec4<f32>(0.0);
    let ds = (sp.sb - sp.sf) / (zb - zf);
    loop {
        var b = zb;
        var next = cur;
        var more = false;
        while (i <= n) {
            let c = textureLoad(crossings, p, i, 0).xy;
            if (!(c.x < zb)) {
                break;
            }
            i++;
            let k = slots[u32(c.y)];
            if (k != cur) {
                b = max(c.x, a);
                next = k;
                more = true;
                break;
            }
        }
        if (cur != CUT && b > a) {
            let c = shade(sp.sf + (a - zf) * ds, sp.sf + (b - zf) * ds, (b - a) * sp.stretch, cur);
            acc += (1.0 - acc.w) * c;
        }
        if (!more) {
            break;
        }
        a = b;
        cur = next;
    }
    return acc;
}

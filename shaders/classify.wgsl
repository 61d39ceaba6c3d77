// Projected tetrahedra, stage 1 (one invocation per tet): project the four vertices, classify the
// projection exactly (Shirley-Tuchman classes from the signs of the four projected face areas on
// the 1/256-pixel grid, in emulated 64-bit integers, as the CPU path does), and write the tet's 5
// vertices: slot 0 the thick point, slots 1-4 the silhouette in order (a triangle repeats its first
// corner), so that the fixed fan (0,1,2) (0,2,3) (0,3,4) (0,4,1) gives its 3 or 4 triangles; fan
// triangles of zero area (classes 3 and 4) produce no fragments.
//
// Each vertex carries (Sf, Sb, l) in homogeneous form, (pf, qf, pb, qb): under perspective
// p = 1/z and q = s/z of the entry (f) and exit (b) points, both exactly linear in screen space
// across a Shirley-Tuchman triangle (one front plane, one back plane); under parallel projection
// p = z and q = s. The fragment stage recovers Sf = qf/pf, Sb = qb/pb and l from the depths.
// Positions are the unsnapped projections, as the CPU path's depth and scalar planes use them;
// the rasterizer snaps them to its own sub-pixel grid (1/256 pixel on llvmpipe, as on the CPU).

@group(0) @binding(0) var<uniform> fr: Frame;
@group(0) @binding(1) var<storage, read> points: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> tets: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read> scalars: array<f32>;
// 5 vertices per tet, 6 floats each: x, y (clip space), pf, qf, pb, qb.
@group(0) @binding(4) var<storage, read_write> verts: array<f32>;
// Class counts 1, 2, 3, 4, flat, then clipped.
@group(0) @binding(5) var<storage, read_write> counts: array<atomic<u32>, 8>;

const SUB: f32 = 256.0;
// Fixed-point guard band (1/256 pixel units), as on the CPU.
const GUARD: f32 = 268435456.0;

// Faces opposite each vertex, consistently oriented (as pt::FACES).
const FACES_C = array<vec3<u32>, 4>(
    vec3<u32>(1u, 2u, 3u),
    vec3<u32>(0u, 3u, 2u),
    vec3<u32>(0u, 1u, 3u),
    vec3<u32>(0u, 2u, 1u),
);

// Round half away from zero (f64::round on the CPU); exact for |x| < 2^31.
fn round_away(x: f32) -> f32 {
    let a = abs(x);
    var t = floor(a);
    if (a - t >= 0.5) {
        t = t + 1.0;
    }
    return select(t, -t, x < 0.0);
}

fn finite(x: f32) -> bool {
    return abs(x) <= 3.4e38;
}

// 64-bit two's complement integers as (lo, hi).
fn mul64(a: i32, b: i32) -> vec2<u32> {
    // |a|, |b| < 2^30 here (guard band), so the middle sum cannot overflow.
    let ua = u32(abs(a));
    let ub = u32(abs(b));
    let a0 = ua & 0xffffu;
    let a1 = ua >> 16u;
    let b0 = ub & 0xffffu;
    let b1 = ub >> 16u;
    let p00 = a0 * b0;
    let mid = a0 * b1 + a1 * b0;
    let p11 = a1 * b1;
    let lo = p00 + (mid << 16u);
    let carry = select(0u, 1u, lo < p00);
    let hi = p11 + (mid >> 16u) + carry;
    if ((a < 0) != (b < 0)) {
        let nlo = ~lo + 1u;
        let nhi = ~hi + select(0u, 1u, nlo == 0u);
        return vec2<u32>(nlo, nhi);
    }
    return vec2<u32>(lo, hi);
}

fn sub64(x: vec2<u32>, y: vec2<u32>) -> vec2<u32> {
    let lo = x.x - y.x;
    let borrow = select(0u, 1u, x.x < y.x);
    return vec2<u32>(lo, x.y - y.y - borrow);
}

fn sign64(x: vec2<u32>) -> i32 {
    if (bitcast<i32>(x.y) < 0) {
        return -1;
    }
    if (x.x == 0u && x.y == 0u) {
        return 0;
    }
    return 1;
}

// Twice the signed area of (a, b, c) in fixed point, exactly.
fn orient2(a: vec2<i32>, b: vec2<i32>, c: vec2<i32>) -> vec2<u32> {
    return sub64(mul64(b.x - a.x, c.y - a.y), mul64(b.y - a.y, c.x - a.x));
}

// Twice the signed area of a pixel-space triangle, in floats (for interpolation weights; the
// class comes from the exact fixed-point signs).
fn area(a: vec2<f32>, b: vec2<f32>, c: vec2<f32>) -> f32 {
    let u = b - a;
    let v = c - a;
    return u.x * v.y - u.y * v.x;
}

fn write_vertex(slot: u32, pos: vec2<f32>, attr: vec4<f32>) {
    let o = slot * 6u;
    verts[o] = pos.x;
    verts[o + 1u] = pos.y;
    verts[o + 2u] = attr.x;
    verts[o + 3u] = attr.y;
    verts[o + 4u] = attr.z;
    verts[o + 5u] = attr.w;
}

// All five vertices on one point outside the view: every fan triangle is empty.
fn write_empty(t: u32) {
    for (var k = 0u; k < 5u; k++) {
        write_vertex(t * 5u + k, vec2<f32>(-4.0, -4.0), vec4<f32>(0.0));
    }
}

// Clip-space position of a pixel-space point (y down).
fn clip_of(p: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(p.x * 2.0 / fr.size.x - 1.0, 1.0 - p.y * 2.0 / fr.size.y);
}

@compute @workgroup_size(64)
fn classify(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let t = gid.x + gid.y * nwg.x * 64u;
    if (t >= fr.flags.x) {
        return;
    }
    let parallel = fr.flags.y != 0u;
    var faces = FACES_C;
    let tv = tets[t];
    var fp: array<vec2<i32>, 4>;
    var pix: array<vec2<f32>, 4>;
    var attr: array<vec2<f32>, 4>;
    var ok = true;
    for (var k = 0u; k < 4u; k++) {
        let d = points[tv[k]].xyz - fr.eye.xyz;
        let v = vec3<f32>(dot(d, fr.r.xyz), dot(d, fr.u.xyz), dot(d, fr.f.xyz));
        var sx: f32;
        var sy: f32;
        if (parallel) {
            sx = v.x / fr.size.z;
            sy = v.y / fr.size.z;
        } else {
            if (!(v.z > fr.eye.w)) {
                ok = false;
                continue;
            }
            sx = v.x / (v.z * fr.size.z);
            sy = v.y / (v.z * fr.size.z);
        }
        let px = (sx / fr.size.w + 1.0) * 0.5 * fr.size.x;
        let py = (1.0 - sy) * 0.5 * fr.size.y;
        let fx = px * SUB;
        let fy = py * SUB;
        if (!(abs(fx) < GUARD && abs(fy) < GUARD && finite(v.x) && finite(v.y) && finite(v.z))) {
            ok = false;
            continue;
        }
        let ix = i32(round_away(fx));
        let iy = i32(round_away(fy));
        fp[k] = vec2<i32>(ix, iy);
        pix[k] = vec2<f32>(px, py);
        var s: f32;
        if (fr.flags.z != 0u) {
            s = scalars[t];
        } else {
            s = scalars[tv[k]];
        }
        if (parallel) {
            attr[k] = vec2<f32>(v.z, s);
        } else {
            let w = 1.0 / v.z;
            attr[k] = vec2<f32>(w, s * w);
        }
    }
    if (!ok) {
        atomicAdd(&counts[5], 1u);
        write_empty(t);
        return;
    }

    var d: array<vec2<u32>, 4>;
    var sg: array<i32, 4>;
    var npos = 0u;
    var nneg = 0u;
    for (var i = 0u; i < 4u; i++) {
        let f = faces[i];
        d[i] = orient2(fp[f.x], fp[f.y], fp[f.z]);
        sg[i] = sign64(d[i]);
        if (sg[i] > 0) {
            npos++;
        } else if (sg[i] < 0) {
            nneg++;
        }
    }
    var cls = 4u;
    if ((npos == 3u && nneg == 1u) || (npos == 1u && nneg == 3u)) {
        cls = 0u;
    } else if (npos == 2u && nneg == 2u) {
        cls = 1u;
    } else if ((npos == 2u && nneg == 1u) || (npos == 1u && nneg == 2u)) {
        cls = 2u;
    } else if (npos == 1u && nneg == 1u) {
        cls = 3u;
    }
    atomicAdd(&counts[cls], 1u);
    if (cls == 4u) {
        write_empty(t);
        return;
    }

    var thick: vec2<f32>;
    var a1: vec2<f32>;
    var a2: vec2<f32>;
    var sil: array<u32, 4>;
    if (npos == 1u || nneg == 1u) {
        // Classes 1, 3, 4: vertex `lone` projects inside (or onto the border of) the triangle of
        // the face opposite it, whose three vertices form the silhouette; the ray through it
        // meets that face at the barycentrics of its projection.
        var want = -1;
        if (npos == 1u) {
            want = 1;
        }
        var lone = 0u;
        for (var i = 0u; i < 4u; i++) {
            if (sg[i] == want) {
                lone = i;
            }
        }
        let f = faces[lone];
        let wx = area(pix[lone], pix[f.y], pix[f.z]);
        let wy = area(pix[f.x], pix[lone], pix[f.z]);
        let wz = area(pix[f.x], pix[f.y], pix[lone]);
        thick = pix[lone];
        a1 = attr[lone];
        a2 = (wx * attr[f.x] + wy * attr[f.y] + wz * attr[f.z]) / (wx + wy + wz);
        sil = array<u32, 4>(f.x, f.y, f.z, f.x);
    } else {
        // Class 2: positive faces i, j share edge k-l; the projected edges i-j and k-l cross at
        // the thick point.
        var pos: array<u32, 2>;
        var neg: array<u32, 2>;
        var np = 0u;
        var nn = 0u;
        for (var i = 0u; i < 4u; i++) {
            if (sg[i] > 0) {
                pos[np] = i;
                np++;
            } else {
                neg[nn] = i;
                nn++;
            }
        }
        let i = pos[0];
        let j = pos[1];
        let k = neg[0];
        let l = neg[1];
        // Where line k-l cuts i-j, and line i-j cuts k-l.
        let ai = area(pix[k], pix[l], pix[i]);
        let aj = area(pix[k], pix[l], pix[j]);
        let ak = area(pix[i], pix[j], pix[k]);
        let al = area(pix[i], pix[j], pix[l]);
        let tij = ai / (ai - aj);
        let tkl = ak / (ak - al);
        thick = pix[i] + (pix[j] - pix[i]) * tij;
        a1 = attr[i] + (attr[j] - attr[i]) * tij;
        a2 = attr[k] + (attr[l] - attr[k]) * tkl;
        sil = array<u32, 4>(i, k, j, l);
    }
    // Entry is the nearer point: larger 1/z under perspective, smaller z under parallel.
    var a1_front = a1.x > a2.x;
    if (parallel) {
        a1_front = a1.x < a2.x;
    }
    var tattr = vec4<f32>(a2, a1);
    if (a1_front) {
        tattr = vec4<f32>(a1, a2);
    }
    write_vertex(t * 5u, clip_of(thick), tattr);
    for (var n = 0u; n < 4u; n++) {
        let k = sil[n];
        write_vertex(t * 5u + 1u + n, clip_of(pix[k]), vec4<f32>(attr[k], attr[k]));
    }
}

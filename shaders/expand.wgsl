// Projected tetrahedra, stage 2: the index buffer from the visibility order. Position i of the
// order draws tet order[i] as the fan (0,1,2) (0,2,3) (0,3,4) (0,4,1) of its 5 vertices, so the
// triangles reach the blender in the order's sequence.

struct Count {
    n: vec4<u32>,
}

@group(0) @binding(0) var<uniform> count: Count;
@group(0) @binding(1) var<storage, read> order: array<u32>;
@group(0) @binding(2) var<storage, read_write> indices: array<u32>;

const FAN_C = array<u32, 12>(0u, 1u, 2u, 0u, 2u, 3u, 0u, 3u, 4u, 0u, 4u, 1u);

@compute @workgroup_size(64)
fn expand(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = gid.x + gid.y * nwg.x * 64u;
    if (i >= count.n.x) {
        return;
    }
    var fan = FAN_C;
    let base = order[i] * 5u;
    for (var k = 0u; k < 12u; k++) {
        indices[i * 12u + k] = base + fan[k];
    }
}

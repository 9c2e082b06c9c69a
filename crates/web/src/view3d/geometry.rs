//! The meshes the 3D view builds, as free functions: spheres, prisms (rods), quads, volume nets,
//! surfaces and contour stacks, and their floats for the page.

use super::*;

/// A volume's control points as spheres coloured by ξ (the selected one orange and larger, those
/// of the slice the 2D view edits full size, the others smaller), the slice's net as rods and its
/// plane, placed by `map` (part coordinates to space), `r` a sphere's radius.
pub(super) fn volume_net(
    editor: &Editor,
    volume: &Solid3,
    map: DAffine3,
    r: f64,
    (opaque, translucent): (&mut Vec<MeshVertex>, &mut Vec<MeshVertex>),
) {
    let (axis, index) = editor.slice().unwrap_or((Axis::W, 0));
    let net = volume.net();
    let scale = net.points().iter().fold(1e-12f64, |m, p| m.max(p.w.abs()));
    let selected = editor
        .selected()
        .and_then(|(p, q)| net.flat_index(axis.embed(index, [p, q])));
    let detail = sphere_detail(net.points().len());
    for (k, p) in net.points().iter().enumerate() {
        let on_slice = net
            .multi_index(k)
            .is_some_and(|ijk| ijk[axis.index()] == index);
        let (radius, color) = match (selected == Some(k), on_slice) {
            (true, _) => (r * 1.3, SELECT_COLOR),
            (false, true) => (r, diverging(p.w / scale)),
            (false, false) => (r * 0.7, diverging(p.w / scale)),
        };
        sphere(
            opaque,
            map.transform_point3(p.truncate()),
            radius,
            color,
            detail,
        );
    }
    if let Some(slice) = net.slice(axis, index) {
        let [n, m] = slice.degree();
        let at = |p: usize, q: usize| map.transform_point3(slice[[p, q]].truncate());
        net_rods(opaque, (n, m), at, r);
        translucent.extend(quad([at(0, 0), at(n, 0), at(n, m), at(0, m)], SLICE_COLOR));
    }
}

/// The rods of a control net of `(n + 1) × (m + 1)` points at `at(i, j)`, `r` being a sphere's
/// radius.
pub(super) fn net_rods(
    out: &mut Vec<MeshVertex>,
    (n, m): (usize, usize),
    at: impl Fn(usize, usize) -> DVec3,
    r: f64,
) {
    for i in 0..=n {
        for j in 0..=m {
            if i < n {
                prism(out, at(i, j), at(i + 1, j), r * 0.12, NET_COLOR);
            }
            if j < m {
                prism(out, at(i, j), at(i, j + 1), r * 0.12, NET_COLOR);
            }
        }
    }
}

/// A flat quadrilateral (corners in order) as two triangles of one colour.
pub(super) fn quad(c: [DVec3; 4], color: Rgba) -> [MeshVertex; 6] {
    let normal = (c[1] - c[0])
        .cross(c[3] - c[0])
        .normalize_or(DVec3::Z)
        .as_vec3()
        .to_array();
    [c[0], c[1], c[2], c[0], c[2], c[3]].map(|p| MeshVertex {
        position: p.as_vec3().to_array(),
        normal,
        color,
    })
}

/// How near `f = 0` the vertices of a drawn surface are put (in `f`).
pub(super) const SURFACE_ACCURACY: f64 = 1e-7;

/// The surface drawn for a volume at `resolution`: the exact surface where the map is regular or
/// certified injective, every sheet where it may fold (`Solid3::polygonize_sheets`, no inverse map).
#[must_use]
pub fn surface_mesh(volume: &Solid3, resolution: usize) -> Option<bezsolid_core::mesh::Mesh> {
    let folded = volume.inverse().is_some_and(|m| !m.injective());
    if folded {
        volume.polygonize_sheets(resolution, SURFACE_ACCURACY)
    } else {
        volume.polygonize(resolution, SURFACE_ACCURACY)
    }
    .ok()
}

/// [`surface_mesh`] as six `f32` per vertex (position, normal), three vertices per triangle: what
/// a Web Worker hands to [`View3::set_surface`].
#[must_use]
pub fn surface_floats(volume: &Solid3, resolution: usize) -> Vec<f32> {
    surface_mesh(volume, resolution).map_or_else(Vec::new, |m| mesh_floats(&m))
}

/// The share `share` of [`surface_floats`]: the shares' floats, one after another, are its floats.
#[must_use]
pub fn surface_share_floats(volume: &Solid3, resolution: usize, share: Share) -> Vec<f32> {
    let folded = volume.inverse().is_some_and(|m| !m.injective());
    if folded {
        volume.polygonize_sheets_share(resolution, SURFACE_ACCURACY, share)
    } else {
        volume.polygonize_share(resolution, SURFACE_ACCURACY, share)
    }
    .map_or_else(|_| Vec::new(), |piece| mesh_floats(&piece.mesh))
}

/// A mesh as six `f32` per vertex (position, normal), three vertices per triangle: the form in
/// which surfaces come back from a Web Worker.
#[must_use]
pub fn mesh_floats(mesh: &bezsolid_core::mesh::Mesh) -> Vec<f32> {
    let mut out = Vec::with_capacity(mesh.triangles.len() * 18);
    for t in &mesh.triangles {
        for &i in t {
            out.extend(mesh.positions[i as usize].as_vec3().to_array());
            out.extend(mesh.normals[i as usize].as_vec3().to_array());
        }
    }
    out
}

/// `spec` cut at the plane `p[axis] = at`: its intersection with the half-space `p[axis] ≤ at`,
/// whose surface is the solid's below the plane closed by the cut face.
#[must_use]
pub fn capped(spec: SolidSpec, (axis, at): (usize, f64)) -> SolidSpec {
    let mut normal = [0.0; 3];
    normal[axis] = 1.0;
    SolidSpec::Intersection {
        of: vec![spec, SolidSpec::Halfspace { normal, offset: at }],
    }
}

/// The surface of `editor`'s volume cut at `cap` ([`capped`]), made as a model of many solids is.
/// The surface of the editor's model as its file is meshed (a piecewise volume cell by cell),
/// cut and closed by `cap` where there is one.
pub(super) fn model_vertices(
    editor: &Editor,
    cap: Option<(usize, f64)>,
    resolution: usize,
) -> Vec<MeshVertex> {
    let solid = crate::document::model_file(editor).solid;
    let file = ModelFile::from_spec(match cap {
        Some(cap) => capped(solid, cap),
        None => solid,
    });
    serde_json::to_string(&file)
        .ok()
        .and_then(|json| crate::document::headless::surface(&json, resolution).ok())
        .map_or_else(Vec::new, |m| float_vertices(&m.data, SURFACE_COLOR))
}

pub(super) fn surface_vertices(volume: &Solid3, resolution: usize) -> Vec<MeshVertex> {
    float_vertices(&surface_floats(volume, resolution), SURFACE_COLOR)
}

/// The zero contour of each slice of the volume across `axis`, placed at the slice's mean position
/// along it, as segments: six `f64` each (its two ends). `progress(done, total)` is called after
/// each slice. A slice whose net may fold costs the inverse map at every sample (seconds at high
/// degree): the page runs this in its worker. With the segments, how many evaluations ran out of
/// their work budget (where a slice folds over itself very many times; 0 where the stack is exact).
pub fn stack_segments(
    volume: &Solid3,
    axis: Axis,
    progress: impl FnMut(usize, usize),
) -> (Vec<f64>, usize) {
    stack_share_segments(volume, axis, Share::WHOLE, progress)
}

/// The slices of share `share` of [`stack_segments`] (runs of slices in order): the shares'
/// segments, one after another, are its segments. `progress(done, total)` after each of the
/// share's slices.
pub fn stack_share_segments(
    volume: &Solid3,
    axis: Axis,
    share: Share,
    mut progress: impl FnMut(usize, usize),
) -> (Vec<f64>, usize) {
    let net = volume.net();
    let a = axis.index();
    let (lo, hi) = axis.others();
    let (lo, hi) = (lo.index(), hi.index());
    let slices = share.range(net.dims()[a]);
    let (first, total) = (slices.start, slices.len());
    let mut out = Vec::new();
    let mut approximate = 0;
    for index in slices {
        if let Some(solid) = volume.slice(axis, index) {
            let along = patch_mean_along(net, axis, index);
            let to3 = |p: DVec2| {
                let mut v = [0.0; 3];
                v[lo] = p.x;
                v[hi] = p.y;
                v[a] = along;
                v
            };
            for line in solid_contour(&solid, STACK_CELLS, 1e-7) {
                let count = if line.closed {
                    line.points.len()
                } else {
                    line.points.len().saturating_sub(1)
                };
                for k in 0..count {
                    let (p, q) = (line.points[k], line.points[(k + 1) % line.points.len()]);
                    out.extend(to3(p));
                    out.extend(to3(q));
                }
            }
            approximate += solid.exhausted();
        }
        progress(index + 1 - first, total);
    }
    (out, approximate)
}

/// The rods that draw a contour stack's segments ([`stack_segments`]) for `volume`.
#[must_use]
pub fn stack_vertices(volume: &Solid3, segments: &[f64]) -> Vec<MeshVertex> {
    let (min, max) = volume.domain();
    let r = (max - min).max_element() * SPHERE_RADIUS * 0.14;
    let mut stack = Vec::with_capacity(segments.len() / 6 * 24);
    for s in segments.chunks_exact(6) {
        let (p, q) = (DVec3::new(s[0], s[1], s[2]), DVec3::new(s[3], s[4], s[5]));
        prism(&mut stack, p, q, r, CONTOUR_COLOR);
    }
    stack
}

/// The mean coordinate along `axis` of the control points of slice `index` across it.
pub(super) fn patch_mean_along(
    net: &bezsolid_core::Volume<DVec4>,
    axis: Axis,
    index: usize,
) -> f64 {
    let a = axis.index();
    let Some(slice) = net.slice(axis, index) else {
        return 0.0;
    };
    let sum: f64 = slice.points().iter().map(|p| p[a]).sum();
    sum / slice.points().len() as f64
}

/// Where the ray `o + t·d` meets the plane through `p` with normal `n` (in front of the eye).
pub(super) fn plane_hit(o: DVec3, d: DVec3, p: DVec3, n: DVec3) -> Option<DVec3> {
    let denom = d.dot(n);
    if denom.abs() < 1e-12 {
        return None;
    }
    let t = (p - o).dot(n) / denom;
    (t > 0.0).then(|| o + d * t)
}

/// The lowest and highest ξ of the control points.
pub(super) fn xi_range(editor: &Editor) -> (f64, f64) {
    editor
        .solid()
        .net()
        .points()
        .iter()
        .fold((0.0f64, 0.0f64), |(lo, hi), p| (lo.min(p.z), hi.max(p.z)))
}

/// The most triangles the control points' spheres of one scene may take: past it they are drawn
/// coarser. A degree-16 volume has 4,913 points; at 192 triangles each (943 k triangles, 113 MB
/// of vertices) building its scene took 0.6 s on the page's thread, at every edit.
pub(super) const SPHERE_TRIANGLES: usize = 200_000;

/// Rings and segments of a sphere, finest first: 192, 96, 48 and 24 triangles.
pub(super) const SPHERE_DETAIL: [(usize, usize); 4] = [(8, 12), (6, 8), (4, 6), (3, 4)];

/// The finest sphere of which `count` fit in [`SPHERE_TRIANGLES`] (the coarsest past that).
pub(super) fn sphere_detail(count: usize) -> (usize, usize) {
    SPHERE_DETAIL
        .into_iter()
        .find(|(r, s)| count * r * s * 2 <= SPHERE_TRIANGLES)
        .unwrap_or(SPHERE_DETAIL[SPHERE_DETAIL.len() - 1])
}

/// A UV sphere of `rings × segments` quads (its directions computed once per ring and segment,
/// not per corner: a 16 × 16 net's spheres are built at every edit).
pub(crate) fn sphere(
    out: &mut Vec<MeshVertex>,
    c: DVec3,
    r: f64,
    color: Rgba,
    (rings, segments): (usize, usize),
) {
    let rings_at: Vec<(f64, f64)> = (0..=rings)
        .map(|i| (core::f64::consts::PI * i as f64 / rings as f64).sin_cos())
        .collect();
    let segments_at: Vec<(f64, f64)> = (0..=segments)
        .map(|j| (core::f64::consts::TAU * j as f64 / segments as f64).sin_cos())
        .collect();
    let corners: Vec<MeshVertex> = rings_at
        .iter()
        .flat_map(|&(st, ct)| {
            segments_at.iter().map(move |&(sp, cp)| {
                let n = DVec3::new(st * cp, st * sp, ct);
                MeshVertex {
                    position: (c + n * r).as_vec3().to_array(),
                    normal: n.as_vec3().to_array(),
                    color,
                }
            })
        })
        .collect();
    let at = |i: usize, j: usize| corners[i * (segments + 1) + j];
    out.reserve(rings * segments * 6);
    for i in 0..rings {
        for j in 0..segments {
            out.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            out.extend([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
}

/// A thin square prism from `a` to `b`.
pub(crate) fn prism(out: &mut Vec<MeshVertex>, a: DVec3, b: DVec3, r: f64, color: Rgba) {
    let axis = b - a;
    if axis.length() < 1e-12 {
        return;
    }
    // glam's `any_orthonormal_vector` takes a unit vector: of a longer one it is no unit (the
    // frame's edges along one axis came out as slabs as wide as the edge was long).
    let dir = axis.normalize();
    let u = dir.any_orthonormal_vector() * r;
    let v = dir.cross(u);
    let corners = [u + v, -u + v, -u - v, u - v];
    for k in 0..4 {
        let (p, q) = (corners[k], corners[(k + 1) % 4]);
        let n = (p + q).normalize().as_vec3().to_array();
        let vx = |x: DVec3| MeshVertex {
            position: x.as_vec3().to_array(),
            normal: n,
            color,
        };
        out.extend([
            vx(a + p),
            vx(b + p),
            vx(b + q),
            vx(a + p),
            vx(b + q),
            vx(a + q),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn a_prism_is_thin_whatever_its_length_and_direction() {
        let r = 0.01;
        for (a, b) in [
            (DVec3::new(-9.0, -9.0, 0.0), DVec3::new(9.0, -9.0, 0.0)),
            (DVec3::new(-9.0, -9.0, 0.0), DVec3::new(-9.0, 9.0, 0.0)),
            (DVec3::new(-9.0, -9.0, 0.0), DVec3::new(-9.0, -9.0, 40.0)),
            (DVec3::new(1.0, 2.0, 3.0), DVec3::new(-70.0, 5.0, 9.0)),
        ] {
            let mut out = Vec::new();
            prism(&mut out, a, b, r, [1.0; 4]);
            assert_eq!(out.len(), 24);
            let dir = (b - a).normalize();
            for v in &out {
                let p = DVec3::from(v.position.map(f64::from)) - a;
                let off = (p - dir * p.dot(dir)).length();
                assert!(off <= r * 1.5, "{a} → {b}: a vertex {off} from the axis");
            }
        }
    }
}

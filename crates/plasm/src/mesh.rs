//! From complexes to geometry: triangles with smooth normals, segments and points in 3D, and the
//! OBJ text of a script's results.
//!
//! Triangles are oriented from the geometry, not from the order of a cell's vertices (see
//! [`triangles`]): a solid's boundary faces outward whichever way its map turns space, and a
//! surface's triangles agree across every edge they share.

use std::fmt::Write as _;

use bezsolid_core::mesh::{Format, Mesh};
use glam::DVec3;

use crate::complex::Complex;

/// A point of a complex in 3D: its first three coordinates, zero-padded (a plane curve lies in
/// z = 0).
pub fn embed(p: &[f64]) -> DVec3 {
    DVec3::new(
        p.first().copied().unwrap_or(0.0),
        p.get(1).copied().unwrap_or(0.0),
        p.get(2).copied().unwrap_or(0.0),
    )
}

/// What a set of complexes shows: triangles (of 2-cells, and the boundary of 3-cells, oriented by
/// [`triangles`]),
/// segments (1-cells) and points (0-cells), all in 3D.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Geometry {
    /// The triangles' mesh, with area-weighted vertex normals; vertices are shared within one
    /// complex.
    pub mesh: Mesh,
    /// Segments, as pairs of points.
    pub segments: Vec<[DVec3; 2]>,
    /// Points.
    pub points: Vec<DVec3>,
    /// The edges of the triangles (each once), for a wireframe.
    pub edges: Vec<[DVec3; 2]>,
}

impl Geometry {
    /// The geometry of `complexes`, one after another.
    pub fn of<'a>(complexes: impl IntoIterator<Item = &'a Complex>) -> Geometry {
        let mut g = Geometry::default();
        for c in complexes {
            g.add(c);
        }
        g.mesh.normals = vertex_normals(&g.mesh);
        g
    }

    fn add(&mut self, c: &Complex) {
        let base = self.mesh.positions.len() as u32;
        let n = c.point_count();
        match c.order {
            1 => self
                .points
                .extend(c.cells.iter().map(|&i| embed(c.point(i as usize)))),
            2 => self.segments.extend(
                (0..c.cell_count())
                    .map(|k| c.cell(k))
                    .map(|s| [embed(c.point(s[0] as usize)), embed(c.point(s[1] as usize))]),
            ),
            _ => {
                self.mesh
                    .positions
                    .extend((0..n).map(|i| embed(c.point(i))));
                let start = self.mesh.triangles.len();
                self.mesh.triangles.extend(
                    triangles(c)
                        .unwrap_or_default()
                        .into_iter()
                        .map(|t| t.map(|i| i + base)),
                );
                let mut keys: Vec<(u32, u32)> = self.mesh.triangles[start..]
                    .iter()
                    .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                    .map(|(a, b)| (a.min(b), a.max(b)))
                    .collect();
                keys.sort_unstable();
                keys.dedup();
                let p = &self.mesh.positions;
                self.edges
                    .extend(keys.iter().map(|&(a, b)| [p[a as usize], p[b as usize]]));
            }
        }
    }

    /// The smallest box holding everything, if anything.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let all = self
            .mesh
            .positions
            .iter()
            .chain(self.segments.iter().flatten())
            .chain(&self.points);
        all.fold(None, |b, &p| match b {
            None => Some((p, p)),
            Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
        })
    }

    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.mesh.triangles.is_empty() && self.segments.is_empty() && self.points.is_empty()
    }
}

/// The triangles that show a complex of triangles or of tetrahedra (`None` for another),
/// oriented however its cells were:
///
/// - triangles: each connected piece (triangles joined across edges that two of them share) is
///   turned so that neighbours agree, every shared edge run once each way; a piece keeps the
///   winding of its first triangle (`MAP` keeps the domain's counter-clockwise cells), and a
///   closed one is turned outward (positive volume);
/// - tetrahedra: the faces that belong to one tetrahedron only (the boundary), turned outward.
///   Each connected piece of tetrahedra (joined across shared faces) is first made consistent
///   (every shared face seen from its two sides), then turned as a whole so that its boundary
///   encloses a positive volume `Σ a · (b × c) / 6`: a cavity's faces point into it. This does not
///   depend on the handedness of a map or of the cells' vertex order (a mirrored map, the
///   unoriented cells of a product outside its full dimension).
#[must_use]
pub fn triangles(c: &Complex) -> Option<Vec<[u32; 3]>> {
    match c.order {
        3 => Some(oriented_surface(c)),
        4 => Some(oriented_boundary(c)),
        _ => None,
    }
}

/// No neighbour across an edge or a face: a boundary, or a place where more than two cells meet.
const NONE: u32 = u32::MAX;

/// Whether the permutation that sorts three distinct numbers is odd.
fn odd(f: [u32; 3]) -> bool {
    (u32::from(f[0] > f[1]) + u32::from(f[0] > f[2]) + u32::from(f[1] > f[2])) % 2 == 1
}

/// Neighbours of `count` cells of `N` sides each, `key(cell, side)` naming a side the same for
/// both cells that have it: per cell and side, the other cell across it where exactly two have
/// it, else [`NONE`]; and the sides that belong to one cell only, as `(cell, side)`.
fn neighbours<K: Ord + Copy, const N: usize>(
    count: usize,
    key: impl Fn(usize, usize) -> K,
) -> (Vec<[u32; N]>, Vec<(u32, u8)>) {
    let mut sides: Vec<(K, u32, u8)> = Vec::with_capacity(count * N);
    for k in 0..count {
        for s in 0..N {
            sides.push((key(k, s), k as u32, s as u8));
        }
    }
    sides.sort_unstable_by_key(|s| s.0);
    let mut across = vec![[NONE; N]; count];
    let mut alone = Vec::new();
    for group in sides.chunk_by(|a, b| a.0 == b.0) {
        match group {
            [(_, k, s)] => alone.push((*k, *s)),
            [(_, a, i), (_, b, j)] if a != b => {
                across[*a as usize][*i as usize] = *b;
                across[*b as usize][*j as usize] = *a;
            }
            _ => {}
        }
    }
    (across, alone)
}

/// Connected pieces of cells joined by `across`, each grown from its first cell, which keeps its
/// orientation: `flip(flipped, from, to)` says whether `to` is flipped, `from` being decided.
/// Gives, per cell, whether it is flipped and its piece's number, and the number of pieces.
fn grow<const N: usize>(
    across: &[[u32; N]],
    flip: impl Fn(&[bool], usize, usize) -> bool,
) -> (Vec<bool>, Vec<u32>, usize) {
    let mut flipped = vec![false; across.len()];
    let mut piece = vec![NONE; across.len()];
    let mut stack = Vec::new();
    let mut pieces = 0;
    for seed in 0..across.len() {
        if piece[seed] != NONE {
            continue;
        }
        piece[seed] = pieces;
        stack.push(seed);
        while let Some(k) = stack.pop() {
            for &n in &across[k] {
                let n = n as usize;
                if n != NONE as usize && piece[n] == NONE {
                    piece[n] = pieces;
                    flipped[n] = flip(&flipped, k, n);
                    stack.push(n);
                }
            }
        }
        pieces += 1;
    }
    (flipped, piece, pieces as usize)
}

/// Six times the volume that the triangles `faces` of `c` enclose, `Σ a · (b × c)`, summed per
/// piece (`piece(k)` of triangle `k`, of `n` pieces).
fn volumes(c: &Complex, faces: &[[u32; 3]], piece: impl Fn(usize) -> usize, n: usize) -> Vec<f64> {
    let o = centre(c);
    let mut v = vec![0.0; n];
    for (k, f) in faces.iter().enumerate() {
        let [a, b, d] = f.map(|i| embed(c.point(i as usize)) - o);
        v[piece(k)] += a.dot(b.cross(d));
    }
    v
}

/// The middle of a complex's bounds in 3D: volumes are taken about it, so that a small solid far
/// from the origin loses nothing to cancellation (as [`Mesh::volume`]).
fn centre(c: &Complex) -> DVec3 {
    let (lo, hi) = (0..c.point_count())
        .map(|i| embed(c.point(i)))
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        });
    if lo.is_finite() && hi.is_finite() {
        (lo + hi) * 0.5
    } else {
        DVec3::ZERO
    }
}

/// Side `s` of a triangle: the edge from corner `s` to the next.
fn edge(t: &[u32], s: usize) -> (u32, u32) {
    (t[s], t[(s + 1) % 3])
}

/// The triangles of a complex of triangles, turned to agree (see [`triangles`]).
fn oriented_surface(c: &Complex) -> Vec<[u32; 3]> {
    let tri = |k: usize| -> [u32; 3] {
        let t = c.cell(k);
        [t[0], t[1], t[2]]
    };
    let (across, _) = neighbours::<_, 3>(c.cell_count(), |k, s| {
        let (a, b) = edge(c.cell(k), s);
        (a.min(b), a.max(b))
    });
    // Across a shared edge a → b (as `from` runs it once turned), `to` must run b → a.
    let (flipped, piece, pieces) = grow(&across, |flipped, from, to| {
        let f = tri(from);
        let s = across[from]
            .iter()
            .position(|&n| n as usize == to)
            .unwrap_or(0);
        let (a, b) = if flipped[from] {
            (f[(s + 1) % 3], f[s])
        } else {
            (f[s], f[(s + 1) % 3])
        };
        (0..3).any(|j| edge(c.cell(to), j) == (a, b))
    });
    let mut out: Vec<[u32; 3]> = (0..c.cell_count())
        .map(|k| {
            let [a, b, d] = tri(k);
            if flipped[k] { [a, d, b] } else { [a, b, d] }
        })
        .collect();
    // A closed piece (every edge of every triangle shared) bounds a solid: outward.
    let mut closed = vec![true; pieces];
    for (k, n) in across.iter().enumerate() {
        if n.contains(&NONE) {
            closed[piece[k] as usize] = false;
        }
    }
    let v = volumes(c, &out, |k| piece[k] as usize, pieces);
    for (k, t) in out.iter_mut().enumerate() {
        let p = piece[k] as usize;
        if closed[p] && v[p] < 0.0 {
            t.swap(1, 2);
        }
    }
    out
}

/// The faces of tetrahedron `t` opposite each vertex, `∂[0,1,2,3] = [1,2,3] − [0,2,3] + [0,1,3] −
/// [0,1,2]`: outward when `(t₁ − t₀, t₂ − t₀, t₃ − t₀)` is right-handed.
fn faces_of(t: &[u32]) -> [[u32; 3]; 4] {
    [
        [t[1], t[2], t[3]],
        [t[0], t[3], t[2]],
        [t[0], t[1], t[3]],
        [t[0], t[2], t[1]],
    ]
}

/// A face's vertices in increasing order: the same for both tetrahedra that share it.
fn sorted(mut f: [u32; 3]) -> [u32; 3] {
    f.sort_unstable();
    f
}

/// The boundary faces of a complex of tetrahedra, outward (see [`triangles`]).
fn oriented_boundary(c: &Complex) -> Vec<[u32; 3]> {
    let (across, alone) = neighbours::<_, 4>(c.cell_count(), |k, s| sorted(faces_of(c.cell(k))[s]));
    // Two tetrahedra agree when they give their shared face opposite windings.
    let (flipped, piece, pieces) = grow(&across, |flipped, from, to| {
        let s = across[from]
            .iter()
            .position(|&n| n as usize == to)
            .unwrap_or(0);
        let f = faces_of(c.cell(from))[s];
        let key = sorted(f);
        let g = faces_of(c.cell(to))
            .into_iter()
            .find(|g| sorted(*g) == key)
            .unwrap_or(f);
        // `to` flipped exactly when, unflipped, its winding would equal `from`'s as turned.
        (odd(f) != flipped[from]) == odd(g)
    });
    let mut out: Vec<([u32; 3], u32)> = alone
        .into_iter()
        .map(|(k, s)| {
            let mut f = faces_of(c.cell(k as usize))[s as usize];
            if flipped[k as usize] {
                f.swap(1, 2);
            }
            (f, piece[k as usize])
        })
        .collect();
    let faces: Vec<[u32; 3]> = out.iter().map(|(f, _)| *f).collect();
    let v = volumes(c, &faces, |k| out[k].1 as usize, pieces);
    for (f, p) in &mut out {
        if v[*p as usize] < 0.0 {
            f.swap(1, 2);
        }
    }
    let mut out: Vec<[u32; 3]> = out.into_iter().map(|(f, _)| f).collect();
    out.sort_unstable();
    out
}

/// Area-weighted vertex normals (zero where a vertex has no area around it).
fn vertex_normals(mesh: &Mesh) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; mesh.positions.len()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += n;
        }
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    normals
}

/// The OBJ text of `complexes`: `v` lines, `f` for triangles (and the boundary of tetrahedra,
/// oriented as [`triangles`] says),
/// `l` for segments, `p` for points; one `o` group per complex.
pub fn write_obj<'a>(complexes: impl IntoIterator<Item = &'a Complex>) -> String {
    let mut out = String::from("# written by bezsolid plasm\n");
    let mut base = 1u64;
    for (k, c) in complexes.into_iter().enumerate() {
        let _ = writeln!(out, "o result{}", k + 1);
        for i in 0..c.point_count() {
            let p = embed(c.point(i));
            let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
        }
        let cells: Vec<Vec<u32>> = match triangles(c) {
            Some(t) => t.into_iter().map(|f| f.to_vec()).collect(),
            None => (0..c.cell_count()).map(|i| c.cell(i).to_vec()).collect(),
        };
        let tag = match c.order {
            1 => "p",
            2 => "l",
            _ => "f",
        };
        for cell in cells {
            out.push_str(tag);
            for i in cell {
                let _ = write!(out, " {}", u64::from(i) + base);
            }
            out.push('\n');
        }
        base += c.point_count() as u64;
    }
    out
}

/// Why [`export`] made no file: the complexes have no triangles (only curves or points), which
/// only OBJ can hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoTriangles;

/// The file of `complexes` in `format`: OBJ keeps everything ([`write_obj`]: faces, lines,
/// points); STL and PLY hold the triangles of their [`Geometry`].
///
/// # Errors
///
/// [`NoTriangles`] for STL or PLY of complexes with no triangles.
pub fn export<'a>(
    complexes: impl IntoIterator<Item = &'a Complex>,
    format: Format,
) -> Result<Vec<u8>, NoTriangles> {
    if format == Format::Obj {
        return Ok(write_obj(complexes).into_bytes());
    }
    let g = Geometry::of(complexes);
    if g.mesh.triangles.is_empty() {
        return Err(NoTriangles);
    }
    Ok(format.write(&g.mesh))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Interp, scripts};

    /// The complexes that `src`'s top-level expressions give.
    fn run(src: &str) -> Vec<Complex> {
        let run = Interp::new().run(src);
        assert!(run.error.is_none(), "{src}: {:?}", run.error);
        run.shown
            .iter()
            .filter_map(|s| s.value.as_pol().cloned())
            .collect()
    }

    /// Whether no edge is run twice the same way: triangles that share an edge agree.
    fn consistent(triangles: &[[u32; 3]]) -> bool {
        let mut edges: Vec<(u32, u32)> = triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .collect();
        let n = edges.len();
        edges.sort_unstable();
        edges.dedup();
        edges.len() == n
    }

    /// The closed mesh of a solid, checked, and its volume; the same from its PLY and STL files
    /// and its OBJ faces.
    fn solid_volume(c: &Complex) -> f64 {
        let mesh = Geometry::of([c]).mesh;
        mesh.check_closed_manifold().expect("a closed manifold");
        let v = mesh.volume();
        for format in [Format::Ply, Format::Stl] {
            let bytes = export([c], format).expect("triangles");
            let raw = format.parse(&bytes).expect("parses back");
            let read = Mesh {
                positions: raw.positions,
                normals: Vec::new(),
                triangles: raw.triangles,
            };
            assert!((read.volume() - v).abs() < 1e-6 * v.abs(), "{format}");
        }
        let obj = write_obj([c]);
        let faces: Vec<[u32; 3]> = obj
            .lines()
            .filter_map(|l| l.strip_prefix("f "))
            .map(|l| {
                let i: Vec<u32> = l
                    .split(' ')
                    .map(|w| w.parse::<u32>().expect("index") - 1)
                    .collect();
                [i[0], i[1], i[2]]
            })
            .collect();
        assert_eq!(faces, mesh.triangles);
        v
    }

    #[test]
    fn solid_unit_cube_faces_outward_in_either_handedness() {
        for map in [
            "<S1, S2, S3>",
            "<S1, S2, K:0 - S3>",
            "<S2, S1, S3>",
            "<S3, S1, S2>",
        ] {
            let src =
                format!("MAP:{map}:(interval:<0,1>:2 * interval:<0,1>:2 * interval:<0,1>:3);");
            let c = &run(&src)[0];
            let v = solid_volume(c);
            assert!((v - 1.0).abs() < 1e-12, "{map}: {v}");
            // 6 faces of 2 × 2, 2 × 3 or 2 × 3 squares, two triangles each.
            assert_eq!(
                Geometry::of([c]).mesh.triangles.len(),
                2 * (8 + 12 + 12),
                "{map}"
            );
        }
    }

    #[test]
    fn solid_normals_point_outward() {
        let c = &run(
            "MAP:<S1, S2, K:0 - S3>:(interval:<0,1>:2 * interval:<0,1>:2 * interval:<0,1>:2);",
        )[0];
        let g = Geometry::of([c]);
        let middle = DVec3::new(0.5, 0.5, -0.5);
        for (p, n) in g.mesh.positions.iter().zip(&g.mesh.normals) {
            if *p != middle {
                assert!(n.dot(*p - middle) > 0.0, "{p} {n}");
            }
        }
    }

    /// A solid blended from the planar grid of Scripts 4.5 and 4.8 (Fig. 4's `grid1`), raised by
    /// a cubic Hermite in a third parameter: upward and downward.
    #[test]
    fn solid_blended_by_hermite_faces_outward() {
        let mut src = String::new();
        for s in [scripts::S4_5, scripts::S4_8] {
            src.push_str(s.text);
            src.push('\n');
        }
        src.push_str(
            "DEF lo = <S1:grid1, S2:grid1, K:0>;\nDEF hi = <S1:grid1, S2:grid1, K:1>;\n\
             MAP:(CubicHermite:S3:<lo, hi, <0,0,1>, <0,0,1>>):(Domain:8 * Domain:8 * Domain:2);\n\
             MAP:(CubicHermite:S3:<hi, lo, <0,0,-1>, <0,0,-1>>):(Domain:8 * Domain:8 * Domain:2);\n\
             MAP:(CONS:grid1):(Domain:8 * Domain:8);\n",
        );
        let cs = run(&src);
        let area = Geometry::of([&cs[2]]).mesh.area();
        assert!(area > 0.5);
        for c in &cs[..2] {
            let v = solid_volume(c);
            assert!((v - area).abs() < 1e-9, "{v} ≠ {area}");
        }
    }

    /// The cells of a product outside its full dimension are not oriented (a curve in the plane
    /// times intervals): the surface and the solid are oriented all the same.
    #[test]
    fn unoriented_products_are_oriented() {
        let surface = &run("MAP:[S1, S1]:(interval:<0,1>:4) * interval:<0,1>:2;")[0];
        assert_eq!((surface.order, surface.dim), (3, 3));
        assert!(!consistent(
            &surface
                .cells
                .chunks(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect::<Vec<_>>()
        ));
        let t = triangles(surface).expect("triangles");
        assert!(consistent(&t));
        assert_eq!(t.len(), surface.cell_count());
        let solid = &run(
            "MAP:<S1, S3, S4>:(MAP:[S1, S1]:(interval:<0,1>:2) * interval:<0,1>:2 * interval:<0,1>:2);",
        )[0];
        assert!((solid_volume(solid) - 1.0).abs() < 1e-12);
    }

    /// A 3 × 3 × 3 block of cubes without the middle one: its cavity's faces point into the
    /// cavity, however the block is mirrored or its cells are turned.
    #[test]
    fn solid_with_a_cavity_keeps_it_inward() {
        let i = Complex::interval(0.0, 3.0, 3);
        let block = i
            .product(&i, 1000)
            .and_then(|s| s.product(&i, 1000))
            .expect("a block");
        let mut cells = Vec::new();
        for k in 0..block.cell_count() {
            let t = block.cell(k);
            let mid = t
                .iter()
                .map(|&v| embed(block.point(v as usize)))
                .sum::<DVec3>()
                / 4.0;
            if !(mid.cmpgt(DVec3::ONE).all() && mid.cmplt(DVec3::splat(2.0)).all()) {
                let mut t = [t[0], t[1], t[2], t[3]];
                if k % 3 == 0 {
                    t.swap(0, 3);
                }
                cells.extend(t);
            }
        }
        for mirror in [1.0, -1.0] {
            let points = block
                .points
                .chunks(3)
                .flat_map(|p| [p[0], p[1], mirror * p[2]])
                .collect();
            let c = Complex::new(3, points, 4, cells.clone());
            let v = solid_volume(&c);
            assert!((v - 26.0).abs() < 1e-9, "{v}");
            assert_eq!(Geometry::of([&c]).mesh.euler_characteristic(), 4);
        }
    }

    /// A closed surface made of triangles bounds a solid: outward, whatever its windings.
    #[test]
    fn surface_closed_faces_outward() {
        let points = vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        for cells in [
            vec![0, 1, 2, 0, 1, 3, 0, 2, 3, 1, 2, 3],
            vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        ] {
            let c = Complex::new(3, points.clone(), 3, cells);
            let mesh = Geometry::of([&c]).mesh;
            mesh.check_closed_manifold().expect("closed");
            assert!((mesh.volume() - 1.0 / 6.0).abs() < 1e-15);
        }
    }

    /// The examples' surfaces are consistently oriented as `MAP` made them: nothing is turned.
    #[test]
    fn surface_examples_keep_their_orientation() {
        for e in scripts::EXAMPLES {
            for c in run(&e.source()) {
                match c.order {
                    3 => {
                        let t = triangles(&c).expect("triangles");
                        assert!(consistent(&t), "{}", e.id);
                        assert_eq!(t.concat(), c.cells, "{}", e.id);
                    }
                    4 => assert!(solid_volume(&c) > 0.0, "{}", e.id),
                    _ => assert!(triangles(&c).is_none()),
                }
            }
        }
    }
}

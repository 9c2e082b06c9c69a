//! From complexes to geometry: triangles with smooth normals, segments and points in 3D, and the
//! OBJ text of a script's results.

use std::collections::HashMap;
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

/// What a set of complexes shows: triangles (of 2-cells, and the boundary of 3-cells),
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
                if c.order == 3 {
                    self.mesh.triangles.extend((0..c.cell_count()).map(|k| {
                        let t = c.cell(k);
                        [t[0] + base, t[1] + base, t[2] + base]
                    }));
                } else {
                    self.mesh
                        .triangles
                        .extend(boundary_faces(c).into_iter().map(|t| t.map(|i| i + base)));
                }
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

/// The faces of tetrahedra that belong to one only, turned outward (for positively oriented
/// tetrahedra).
fn boundary_faces(c: &Complex) -> Vec<[u32; 3]> {
    let mut count: HashMap<[u32; 3], ([u32; 3], u32)> = HashMap::new();
    for k in 0..c.cell_count() {
        let t = c.cell(k);
        // Faces opposite each vertex, ordered so that the normal points away from it.
        for f in [
            [t[1], t[3], t[2]],
            [t[0], t[2], t[3]],
            [t[0], t[3], t[1]],
            [t[0], t[1], t[2]],
        ] {
            let mut key = f;
            key.sort_unstable();
            count.entry(key).or_insert((f, 0)).1 += 1;
        }
    }
    let mut out: Vec<[u32; 3]> = count
        .into_values()
        .filter(|(_, n)| *n == 1)
        .map(|(f, _)| f)
        .collect();
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

/// The OBJ text of `complexes`: `v` lines, `f` for triangles (and the boundary of tetrahedra),
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
        let cells: Vec<Vec<u32>> = if c.order == 4 {
            boundary_faces(c).into_iter().map(|f| f.to_vec()).collect()
        } else {
            (0..c.cell_count()).map(|i| c.cell(i).to_vec()).collect()
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

//! Whether triangles bound a solid: the one closed-2-manifold check, which counts every defect.

use alloc::vec::Vec;
use core::fmt;

use glam::DVec3;

/// A triangle is degenerate when its area is at most this times the squared diagonal of the mesh's
/// bounding box: relative, so that the test does not depend on the unit of the file.
const DEGENERATE_AREA: f64 = 1e-12;

/// Every defect that keeps a mesh from bounding a solid, counted (see [`validate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MeshDefects {
    /// Edges used by one triangle only.
    pub open_edges: usize,
    /// Edges used by three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges whose two triangles run them the same direction (one of them is turned over).
    pub inconsistent_edges: usize,
    /// Triangles that repeat a vertex, use a vertex that does not exist, or have (almost) no area.
    pub degenerate_triangles: usize,
    /// Vertices whose triangles form more than one fan (two sheets touch at a point).
    pub non_manifold_vertices: usize,
}

impl MeshDefects {
    /// Whether there are no defects at all.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

impl fmt::Display for MeshDefects {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let items: [(usize, &str, &str); 5] = [
            (self.open_edges, "open edge", "open edges"),
            (
                self.non_manifold_edges,
                "edge shared by more than two triangles",
                "edges shared by more than two triangles",
            ),
            (
                self.inconsistent_edges,
                "inconsistently oriented edge (a triangle is turned over)",
                "inconsistently oriented edges (triangles are turned over)",
            ),
            (
                self.degenerate_triangles,
                "degenerate triangle",
                "degenerate triangles",
            ),
            (
                self.non_manifold_vertices,
                "non-manifold vertex (surfaces touch at a point)",
                "non-manifold vertices (surfaces touch at a point)",
            ),
        ];
        f.write_str("the mesh is not a closed solid")?;
        let mut first = true;
        for (count, one, many) in items {
            if count == 0 {
                continue;
            }
            f.write_str(if first { ": " } else { ", " })?;
            first = false;
            write!(f, "{count} {}", if count == 1 { one } else { many })?;
        }
        Ok(())
    }
}

impl core::error::Error for MeshDefects {}

/// Checks that triangles bound a solid, counting every defect (see [`MeshDefects`]): each
/// undirected edge must have exactly two triangles running it in opposite directions (one is
/// *open*, three or more *non-manifold*, two the same way *inconsistent*); no triangle may repeat a
/// vertex, use one out of range, or have area ≤ 10⁻¹² × (bounding-box diagonal)²; and the triangles
/// around each vertex must be connected through the edges at that vertex (one fan; otherwise the
/// vertex is *non-manifold*). Triangles that repeat a vertex or are out of range take no part in
/// the edge and vertex counts. No triangles at all is no defect here ([`read`](super::read) reports it).
///
/// # Errors
///
/// The counts, when any is nonzero.
pub fn validate(positions: &[DVec3], triangles: &[[u32; 3]]) -> Result<(), MeshDefects> {
    check(positions, triangles, true)
}

/// The one check behind [`validate`] and [`Mesh::check_closed_manifold`](super::Mesh::check_closed_manifold):
/// the topology always, the triangles' areas when `areas` says so.
pub(crate) fn check(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    areas: bool,
) -> Result<(), MeshDefects> {
    let mut defects = MeshDefects::default();
    let (lo, hi) = positions
        .iter()
        .filter(|p| p.is_finite())
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let diagonal2 = if lo.cmple(hi).all() {
        (hi - lo).length_squared()
    } else {
        0.0
    };
    // |(b − a) × (c − a)| = 2·area.
    let min_double_area = 2.0 * DEGENERATE_AREA * diagonal2;
    let mut edges: Vec<(u32, u32, bool)> = Vec::with_capacity(triangles.len() * 3);
    let mut around: Vec<(u32, u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for tri in triangles {
        let Some(p) = corners(positions, tri) else {
            defects.degenerate_triangles += 1;
            continue;
        };
        if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            defects.degenerate_triangles += 1;
            continue;
        }
        if areas && (p[1] - p[0]).cross(p[2] - p[0]).length() <= min_double_area {
            defects.degenerate_triangles += 1;
        }
        for e in 0..3 {
            let (a, b) = (tri[e], tri[(e + 1) % 3]);
            edges.push((a.min(b), a.max(b), a < b));
            // At corner tri[e], the triangle joins its neighbours tri[e + 2] and tri[e + 1].
            around.push((tri[e], tri[(e + 2) % 3], tri[(e + 1) % 3]));
        }
    }
    edges.sort_unstable();
    for group in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1) {
        match group {
            [_] => defects.open_edges += 1,
            [x, y] if x.2 == y.2 => defects.inconsistent_edges += 1,
            [_, _] => {}
            _ => defects.non_manifold_edges += 1,
        }
    }
    // The link of a vertex: its neighbours, joined by each triangle at it. One fan (a disc, or a
    // half-disc at the border) is a connected link; a link in several pieces is two sheets touching.
    around.sort_unstable();
    let mut neighbours: Vec<u32> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    for fan in around.chunk_by(|x, y| x.0 == y.0) {
        neighbours.clear();
        neighbours.extend(fan.iter().flat_map(|c| [c.1, c.2]));
        neighbours.sort_unstable();
        neighbours.dedup();
        parent.clear();
        parent.extend(0..neighbours.len());
        let mut pieces = neighbours.len();
        for c in fan {
            let (Ok(a), Ok(b)) = (
                neighbours.binary_search(&c.1),
                neighbours.binary_search(&c.2),
            ) else {
                continue;
            };
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra != rb {
                if let Some(p) = parent.get_mut(ra) {
                    *p = rb;
                }
                pieces -= 1;
            }
        }
        if pieces > 1 {
            defects.non_manifold_vertices += 1;
        }
    }
    if defects.is_empty() {
        Ok(())
    } else {
        Err(defects)
    }
}

/// The root of `i` in a union–find forest, halving paths on the way.
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while let Some(&p) = parent.get(i) {
        if p == i {
            break;
        }
        let grand = parent.get(p).copied().unwrap_or(p);
        if let Some(slot) = parent.get_mut(i) {
            *slot = grand;
        }
        i = grand;
    }
    i
}

/// The corners of a triangle, or `None` if an index is out of range.
pub(crate) fn corners(positions: &[DVec3], tri: &[u32; 3]) -> Option<[DVec3; 3]> {
    Some([
        *positions.get(tri[0] as usize)?,
        *positions.get(tri[1] as usize)?,
        *positions.get(tri[2] as usize)?,
    ])
}

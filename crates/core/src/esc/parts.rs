//! A free-form result's parts far apart: the boxes of its solids gathered as a tree's are
//! ([`crate::math::far_parts`]), so that each part is meshed on a grid of its own at the
//! resolution asked (a sphere and a torus 1000 apart were less than a cell each on one grid over
//! both, and their union read as empty).

use alloc::vec::Vec;

use glam::DVec3;

use super::bool::{Expr, Op};
use super::draw::Boolean;

/// The most boxes kept for one node: past it they are joined into their hull.
const MAX_BOXES: usize = 64;

impl Boolean {
    /// Boxes holding the result, gathered into parts far apart from each other (one where its
    /// parts are near).
    pub(super) fn far_parts(&self) -> Vec<(DVec3, DVec3)> {
        let all = self.scene_bounds();
        let boxes: Vec<([f64; 3], [f64; 3])> = self
            .boxes(&self.expr, all)
            .into_iter()
            .filter(|(lo, hi)| lo.cmple(*hi).all() && lo.is_finite() && hi.is_finite())
            .map(|(lo, hi)| (lo.to_array(), hi.to_array()))
            .collect();
        crate::math::far_parts(&boxes)
            .into_iter()
            .map(|(lo, hi)| (DVec3::from_array(lo), DVec3::from_array(hi)))
            .collect()
    }

    /// Boxes whose union holds `expr`'s result: a union's are its operands', an intersection's
    /// their overlaps, a difference's its first operand's, a complement's the scene.
    fn boxes(&self, expr: &Expr, all: (DVec3, DVec3)) -> Vec<(DVec3, DVec3)> {
        let hull = |b: &[(DVec3, DVec3)]| {
            b.iter().fold(
                (DVec3::INFINITY, DVec3::NEG_INFINITY),
                |(lo, hi), (a, b)| (lo.min(*a), hi.max(*b)),
            )
        };
        let capped = |b: Vec<(DVec3, DVec3)>| {
            let b: Vec<_> = b
                .into_iter()
                .filter(|(lo, hi)| lo.cmple(*hi).all())
                .collect();
            if b.len() > MAX_BOXES {
                alloc::vec![hull(&b)]
            } else {
                b
            }
        };
        match expr {
            Expr::Solid(i) => self
                .solids
                .get(*i)
                .map(|s| s.bounds())
                .into_iter()
                .collect(),
            Expr::Complement(_) => alloc::vec![all],
            Expr::Binary(op, a, b) => {
                let (a, b) = (self.boxes(a, all), self.boxes(b, all));
                match op {
                    Op::Union => capped(a.into_iter().chain(b).collect()),
                    Op::Difference => a,
                    Op::Intersection if a.len() * b.len() > MAX_BOXES => {
                        let (x, y) = (hull(&a), hull(&b));
                        capped(alloc::vec![(x.0.max(y.0), x.1.min(y.1))])
                    }
                    Op::Intersection => capped(
                        a.iter()
                            .flat_map(|x| b.iter().map(|y| (x.0.max(y.0), x.1.min(y.1))))
                            .collect(),
                    ),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::esc::chain::EscSolid;
    use crate::esc::examples::Example;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    /// A sphere and a torus 1000 and 100 apart: their union's surface is each one's own, closed,
    /// with the sum of their volumes (1000 apart the result read as empty; 100 apart its volume
    /// was 0.55 of the sum).
    #[test]
    fn parts_far_apart_are_drawn_each_where_it_is() {
        let sphere = EscSolid::new(&Example::Icosphere.mesh()).expect("valid");
        for apart in [1000.0, 100.0, -3e4] {
            let mut moved = Example::Torus.mesh();
            for p in &mut moved.positions {
                p.x += apart;
            }
            let torus = EscSolid::new(&moved).expect("valid");
            let alone = |solid: &EscSolid| {
                Boolean {
                    solids: alloc::vec![solid.clone()],
                    expr: Expr::Solid(0),
                }
                .surface(48)
            };
            let (a, b) = (alone(&sphere), alone(&torus));
            let both = Boolean {
                solids: alloc::vec![sphere.clone(), torus.clone()],
                expr: Expr::binary(Op::Union, Expr::Solid(0), Expr::Solid(1)),
            };
            assert_eq!(both.far_parts().len(), 2);
            let mesh = both.surface(48);
            mesh.check_closed_manifold().unwrap();
            assert_eq!(
                mesh.triangle_count(),
                a.triangle_count() + b.triangle_count()
            );
            let sum = a.volume() + b.volume();
            assert!(
                (mesh.volume() - sum).abs() < 1e-6 * sum,
                "{apart}: {}",
                mesh.volume()
            );
        }
    }
}

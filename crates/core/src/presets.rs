//! Preset solids that give recognisable shapes: the first paper's Fig. 9 in 2D, and in 3D a blob, a
//! ring and a fish in the spirit of the paper's Fig. 10, and a "Bézier zoo" in the spirit of its
//! Fig. 12 (a chair, a vase, a twisted ring, a shell, a fish with fins, a tooth), made by us.
//!
//! Each is made with the modeler's own two operations, the paper's: function mapping (the ξ of each
//! control point of a regular grid) and then space mapping (control points moved in space, a map
//! that stays injective, so the solid meshes forward from its parameter box).

use glam::{DVec2, DVec3};

use crate::model::ModelSolid;
use crate::{Solid2, Solid3, Tensor};

/// A preset model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Preset {
    /// The paper's Fig. 9: a degree-(2, 2) patch, one blob in the unit square.
    Fig9,
    /// A degree-(2, 2, 2) volume over `[-1, 1]³`: the centre raised, the corners lowered.
    Blob,
    /// A torus-like ring: degree (6, 6, 2) over `[-1, 1]² × [-0.4, 0.4]`, ξ positive on a circle of
    /// control points in the middle layer.
    Ring,
    /// A fish: degree (6, 4, 2) over `[0, 3] × [−0.8, 0.8] × [−0.5, 0.5]`, a round body, a waist and
    /// a tail fin that is wide in y and thin in z.
    Fish,
    /// An armchair: degree (6, 6, 6), a block hollowed above the seat and below it between four
    /// legs; the legs splayed and the back tilted by moving control points.
    Chair,
    /// A vase: degree (6, 6, 4), a tube (ξ raised on a ring of control points) with a floor, its
    /// layers scaled to a belly, a neck and a lip.
    Vase,
    /// A twisted ring, knot-like: the ring's net (degree (6, 6, 2)) with its inner columns of
    /// points lifted along three waves around the axis and its tube's section tilted with them.
    Knot,
    /// A clam's shell: degree (6, 6, 4), a hollow dome (ξ raised between two radii) fanned from a
    /// hinge and ribbed by moving its points.
    Shell,
    /// A fish with fins: degree (6, 4, 4), the fish's body and tail with a dorsal fin and two side
    /// fins (ξ raised there and their points drawn out), bent as it swims.
    Koi,
    /// A molar: degree (4, 2, 6), a crown whose top carries four cusps, on two roots.
    Tooth,
}

impl Preset {
    /// Every preset, 2D first.
    pub const ALL: [Self; 10] = [
        Self::Fig9,
        Self::Blob,
        Self::Ring,
        Self::Fish,
        Self::Chair,
        Self::Vase,
        Self::Knot,
        Self::Shell,
        Self::Koi,
        Self::Tooth,
    ];

    /// The preset's name in files, links and the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Fig9 => "fig9",
            Self::Blob => "blob",
            Self::Ring => "ring",
            Self::Fish => "fish",
            Self::Chair => "chair",
            Self::Vase => "vase",
            Self::Knot => "knot",
            Self::Shell => "shell",
            Self::Koi => "koi",
            Self::Tooth => "tooth",
        }
    }

    /// The preset called `name`, if any.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The preset's solid.
    #[must_use]
    pub fn solid(self) -> ModelSolid {
        match self {
            Self::Fig9 => ModelSolid::Patch(Solid2::fig9()),
            Self::Blob => ModelSolid::Volume(blob()),
            Self::Ring => ModelSolid::Volume(ring()),
            Self::Fish => ModelSolid::Volume(fish()),
            Self::Chair => ModelSolid::Volume(chair()),
            Self::Vase => ModelSolid::Volume(vase()),
            Self::Knot => ModelSolid::Volume(knot()),
            Self::Shell => ModelSolid::Volume(shell()),
            Self::Koi => ModelSolid::Volume(koi()),
            Self::Tooth => ModelSolid::Volume(tooth()),
        }
    }
}

fn valid(solid: Result<Solid3, crate::SolidError>) -> Solid3 {
    solid.unwrap_or_else(|_| unreachable!("presets are valid regular grids"))
}

fn blob() -> Solid3 {
    valid(Solid3::regular(
        [2, 2, 2],
        DVec3::splat(-1.0),
        DVec3::ONE,
        |index| match index {
            [1, 1, 1] => 1.0,
            [0 | 2, 0 | 2, 0 | 2] => -1.0,
            _ => 0.25,
        },
    ))
}

/// The distance of the control column `(i, j)` of a 7 × 7 grid from its centre, in half-widths
/// of the grid (1 at the middle of a side).
fn ring_radius(i: usize, j: usize) -> f64 {
    DVec2::new(i as f64 / 3.0 - 1.0, j as f64 / 3.0 - 1.0).length()
}

fn ring() -> Solid3 {
    // The middle layer is raised on the control points at radius 0.5 to 1 from the axis and lowered
    // inside (the hole) and outside; the top and bottom layers are lowered a little.
    let min = DVec3::new(-1.0, -1.0, -0.4);
    valid(Solid3::regular([6, 6, 2], min, -min, |[i, j, k]| {
        let r = ring_radius(i, j);
        match (k, r) {
            (1, r) if r > 0.5 && r < 1.0 => 2.0,
            (1, r) if r <= 0.5 => -1.0,
            (1, _) => -0.5,
            _ => -0.3,
        }
    }))
}

// The fish's ξ. Along x (i): nose, head, belly, back, waist, tail root, tail. Across y (j) the rows
// are outer, near, centre, near, outer (`FISH_ROW`); in z (k) the middle layer and the top/bottom
// layers. The body is high in the middle layer and not too low above and below (round); the tail
// is wide in y (the outer rows rise at i = 6) and thin in z (top and bottom well below the middle).
const FISH_MIDDLE: [[f64; 7]; 3] = [
    [-1.0, -1.0, -1.0, -1.0, -1.0, -1.5, 2.6],
    [-1.0, 1.2, 2.4, 2.0, 0.2, 0.8, 1.8],
    [-0.5, 2.5, 3.5, 3.2, 2.6, 3.2, 1.2],
];
const FISH_OUTER: [[f64; 7]; 3] = [
    [-1.2, -1.2, -1.2, -1.2, -1.2, -1.2, -2.2],
    [-1.2, -1.2, -1.2, -1.2, -1.2, -1.2, -1.3],
    [-1.0, -0.2, 0.3, 0.0, -1.0, -1.8, -1.0],
];
const FISH_ROW: [usize; 5] = [0, 1, 2, 1, 0];

fn fish() -> Solid3 {
    valid(Solid3::regular(
        [6, 4, 2],
        DVec3::new(0.0, -0.8, -0.5),
        DVec3::new(3.0, 0.8, 0.5),
        |[i, j, k]| {
            let layer = if k == 1 { &FISH_MIDDLE } else { &FISH_OUTER };
            layer[FISH_ROW[j]][i]
        },
    ))
}

/// The regular grid over `[min, max]` with `ξ(P_I) = xi(I)` (function mapping), whose control
/// points are then moved to `moved(I, P_I)` (space mapping).
fn mapped(
    degree: [usize; 3],
    min: DVec3,
    max: DVec3,
    xi: impl FnMut([usize; 3]) -> f64,
    moved: impl Fn([usize; 3], DVec3) -> DVec3,
) -> Solid3 {
    let grid = valid(Solid3::regular(degree, min, max, xi));
    let net = Tensor::from_fn(degree, |at| {
        let c = grid.net()[at];
        moved(at, c.truncate()).extend(c.w)
    });
    valid(
        net.map_err(crate::SolidError::from)
            .and_then(Solid3::try_from_net),
    )
}

fn chair() -> Solid3 {
    // Solid everywhere but above the seat between the arms and in front of the back, and below
    // the seat between the legs.
    mapped(
        [6, 6, 6],
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(1.0, 1.0, 2.0),
        |[i, j, k]| {
            let arm = i == 0 || i == 6;
            let back = j >= 5;
            let leg = (i <= 1 || i >= 5) && (j <= 1 || j >= 5);
            let above = k >= 4 && !arm && !back;
            let below = k <= 1 && !leg;
            if above || below { -1.0 } else { 1.0 }
        },
        |[_, _, k], p| {
            let t = k as f64 / 6.0;
            // Legs splayed at the floor; the back leans back as it rises.
            let splay = 1.0 + 0.15 * (1.0 - t) * (1.0 - t);
            let lean = if p.y > 0.5 { 0.35 * t * t } else { 0.0 };
            DVec3::new(p.x * splay, p.y * splay + lean, p.z)
        },
    )
}

fn vase() -> Solid3 {
    mapped(
        [6, 6, 4],
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(1.0, 1.0, 3.0),
        |[i, j, k]| {
            let r = ring_radius(i, j);
            match (k, r) {
                (_, r) if r > 1.0 => -0.5,
                (0, _) => 2.0,
                (_, r) if r > 0.5 => 2.0,
                _ => -4.0,
            }
        },
        |[_, _, k], p| {
            const SCALE: [f64; 5] = [0.7, 1.15, 0.9, 0.55, 0.8];
            DVec3::new(p.x * SCALE[k], p.y * SCALE[k], p.z)
        },
    )
}

fn knot() -> Solid3 {
    mapped(
        [6, 6, 2],
        DVec3::new(-1.0, -1.0, -0.5),
        DVec3::new(1.0, 1.0, 0.5),
        |[i, j, k]| {
            let r = ring_radius(i, j);
            match (k, r) {
                (1, r) if r > 0.5 && r < 1.0 => 2.0,
                (1, r) if r <= 0.5 => -1.0,
                (1, _) => -0.5,
                _ => -0.3,
            }
        },
        |[i, j, _], p| {
            // Every inner column of points lifted along three waves around the axis, and its
            // tube's section tilted with them (the outer side lifted more than the inner): a
            // twist. The box's sides stay where they are.
            if i % 6 == 0 || j % 6 == 0 {
                return p;
            }
            let rho = p.truncate().length();
            let theta = libm::atan2(p.y, p.x);
            let lift = 1.5 * rho * libm::sin(3.0 * theta);
            let tilt = 0.5 * (rho - 0.5) * libm::cos(3.0 * theta);
            DVec3::new(p.x, p.y, p.z + lift + tilt)
        },
    )
}

fn shell() -> Solid3 {
    // A dome-shaped wall (ξ raised on control points between two radii from the base's centre,
    // as the ring and the vase raise it on a ring), fanned from a hinge and ribbed by moving the
    // points.
    mapped(
        [6, 6, 4],
        DVec3::new(-1.0, -1.0, 0.0),
        DVec3::new(1.0, 1.0, 1.0),
        |[i, j, k]| {
            let r = DVec3::new(i as f64 / 3.0 - 1.0, j as f64 / 3.0 - 1.0, k as f64 / 4.0).length();
            match r {
                r if r >= 1.0 => -1.0,
                r if r > 0.55 => 2.0,
                _ => -3.0,
            }
        },
        |[i, j, _], p| {
            let t = j as f64 / 6.0;
            let fan = 0.45 + 0.55 * t;
            let rib = 1.0 + if i % 2 == 0 { 0.06 } else { -0.06 } * t;
            DVec3::new(p.x * fan * rib, p.y, p.z)
        },
    )
}

fn koi() -> Solid3 {
    // The fish's layers, with room above for a dorsal fin on the back's centre row and side fins
    // on the outer rows: layer 0 its bottom, 1 and 2 its middle, 3 its top, 4 the fin's tip.
    const FIN: [f64; 7] = [-3.0, -3.0, 6.0, 4.0, -3.0, -3.0, -3.0];
    mapped(
        [6, 4, 4],
        DVec3::new(0.0, -0.8, -0.5),
        DVec3::new(3.0, 0.8, 0.9),
        |[i, j, k]| match k {
            4 if j == 2 => FIN[i],
            4 => -3.0,
            3 if j == 2 && (i == 2 || i == 3) => 2.5,
            1 | 2 if (j == 0 || j == 4) && i == 2 => 3.0,
            0 | 3 => FISH_OUTER[FISH_ROW[j]][i],
            _ => FISH_MIDDLE[FISH_ROW[j]][i],
        },
        |[i, j, k], p| {
            // Bent as it swims; the side fins' points drawn out and back, the dorsal fin's up.
            let bend = 0.15 * libm::sin(core::f64::consts::PI * p.x / 3.0);
            let side = (j == 0 || j == 4) && i == 2 && (k == 1 || k == 2);
            let (x, y) = if side {
                (p.x + 0.3, p.y * 2.0)
            } else {
                (p.x, p.y)
            };
            let z = match (i, j, k) {
                (2, 2, 4) => p.z + 2.5,
                (3, 2, 4) => p.z + 1.5,
                (2 | 3, 2, 3) => p.z + 0.3,
                _ => p.z,
            };
            DVec3::new(x, y + bend, z)
        },
    )
}

fn tooth() -> Solid3 {
    // Solid up to its box, whose top carries four cusps (control points raised at its corners
    // and lowered at its centre), but for the furcation between the two roots.
    mapped(
        [4, 2, 6],
        DVec3::new(-1.0, -0.7, 0.0),
        DVec3::new(1.0, 0.7, 2.4),
        |[i, _, k]| match (k, i) {
            (0..=2, 2) => -6.0,
            (3, 2) => 0.5,
            _ => 1.5,
        },
        |[i, j, k], p| {
            // The crown bulges; the roots narrow and close in towards their tips.
            let x = match (k, i) {
                (4 | 5, _) => p.x * 1.1,
                (0, 0) => -0.8,
                (0, 1) => -0.25,
                (0, 3) => 0.25,
                (0, 4) => 0.8,
                _ => p.x,
            };
            let y = match k {
                0 => p.y * 0.55,
                1 => p.y * 0.8,
                _ => p.y,
            };
            let z = match (k, i, j) {
                (6, 1 | 3, 0 | 2) => p.z + 0.6,
                (6, 2, 1) => p.z - 0.4,
                _ => p.z,
            };
            DVec3::new(x, y, z)
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    #[test]
    fn names_round_trip() {
        for p in Preset::ALL {
            assert_eq!(Preset::from_name(p.name()), Some(p));
        }
        assert_eq!(Preset::from_name("whale"), None);
    }

    #[test]
    fn presets_mesh_to_closed_surfaces_of_the_right_genus() {
        for (preset, euler) in [
            (Preset::Blob, 2),
            (Preset::Ring, 0),
            (Preset::Fish, 2),
            (Preset::Chair, 2),
            (Preset::Vase, 2),
            (Preset::Knot, 0),
            (Preset::Shell, 2),
            (Preset::Koi, 2),
            (Preset::Tooth, 2),
        ] {
            let ModelSolid::Volume(solid) = preset.solid() else {
                panic!("{preset:?} is a volume");
            };
            let mesh = solid.polygonize(48, 1e-9).unwrap();
            mesh.check_closed_manifold().unwrap();
            assert_eq!(mesh.euler_characteristic(), euler, "{preset:?}");
            assert!(
                mesh.volume() > 0.0,
                "{preset:?} {} {}",
                mesh.volume(),
                mesh.triangle_count()
            );
        }
    }

    /// The zoo's presets are space mappings certified injective (they mesh forward from their
    /// parameter box, as the page draws them, with no fold to warn of), and each has the feature it
    /// is named for: a point where the shape must be solid and one where it must be empty.
    #[test]
    fn the_zoo_is_mapped_injectively_and_shaped_as_named() {
        use crate::inverse::Method;
        let cases: [(Preset, [f64; 3], [f64; 3]); 6] = [
            // The seat is solid; the space above it, between the arms, is not.
            (Preset::Chair, [0.0, -0.3, 1.0], [0.0, -0.3, 1.7]),
            // The floor is solid; the vase is hollow above it.
            (Preset::Vase, [0.0, 0.0, 0.2], [0.0, 0.0, 1.5]),
            // The tube is solid; the ring's centre is its hole.
            (Preset::Knot, [0.75, 0.0, 0.0], [0.0, 0.0, 0.0]),
            // The dome's wall is solid; under it is hollow.
            (Preset::Shell, [0.0, 0.0, 0.7], [0.0, 0.0, 0.2]),
            // The crown is solid; between the roots is not.
            (Preset::Tooth, [0.0, 0.0, 1.8], [0.0, 0.0, 0.3]),
            // The body is solid; above the head is not.
            (Preset::Koi, [1.0, 0.0, 0.0], [0.4, 0.0, 0.8]),
        ];
        for (preset, solid, empty) in cases {
            let ModelSolid::Volume(s) = preset.solid() else {
                panic!("{preset:?} is a volume");
            };
            assert!(
                s.inverse()
                    .is_some_and(crate::inverse::InverseMap::injective),
                "{preset:?} is an injective space mapping"
            );
            let f = |p: [f64; 3]| s.evaluate(DVec3::from_array(p), Method::Fast).f;
            assert!(f(solid) > 0.0, "{preset:?} at {solid:?}: {}", f(solid));
            assert!(f(empty) < 0.0, "{preset:?} at {empty:?}: {}", f(empty));
        }
        // The wave lifts the knot's tube: at the top of a wave the tube's centre is well above the
        // plane z = 0, at the bottom of the next well below it.
        let ModelSolid::Volume(knot) = Preset::Knot.solid() else {
            unreachable!()
        };
        let top = |theta: f64| {
            let (y, x) = (0.75 * theta.sin(), 0.75 * theta.cos());
            (0..=200)
                .map(|k| -1.5 + 3.0 * f64::from(k) / 200.0)
                .filter(|&z| knot.evaluate(DVec3::new(x, y, z), Method::Fast).f > 0.0)
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let (up, down) = (
            top(core::f64::consts::PI / 6.0),
            top(core::f64::consts::PI / 2.0),
        );
        assert!(
            up > down + 0.2,
            "the tube's top at the wave's crest {up}, trough {down}"
        );
        // The fish's fins: solid beside its body where the fish without fins is empty.
        let ModelSolid::Volume(koi) = Preset::Koi.solid() else {
            unreachable!()
        };
        let ModelSolid::Volume(fish) = Preset::Fish.solid() else {
            unreachable!()
        };
        let fin = DVec3::new(1.2, 0.8, 0.1);
        assert!(koi.evaluate(fin, Method::Fast).f > 0.0);
        assert!(fish.evaluate(fin, Method::Fast).f < 0.0);
    }
}

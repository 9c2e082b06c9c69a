//! A tree of many solids on the wire: its nodes in prefix order (a node, then its children), each
//! without its children, so that neither writing nor reading recurses, and a link that nests
//! deeper or holds more nodes than a model may is refused before anything is built.
//!
//! The layout of `v1`'s variant `4` (appended: variants `0` to `3` keep theirs) is a sequence of
//! [`Node`]s; an operation says how many children follow it (blends and morphs take 2, a
//! transform and a named part 1). Numbers are postcard's: varints for integers, 8 little-endian bytes per `f64`.

use alloc::boxed::Box;
use alloc::vec::Vec;

use serde::{Deserialize, Serialize};

use super::{LinkError, byte, columns, rows};
use crate::model::{CoordAxis, ModelError, Rotation, SolidSpec};
use crate::tree::{MAX_DEPTH, MAX_NODES, TreeError};

/// One node of a tree, without its children. Variant order and field order are the contract.
#[derive(Serialize, Deserialize)]
pub(super) enum Node {
    Patch {
        degree: [u8; 2],
        x: Vec<f64>,
        y: Vec<f64>,
        xi: Vec<f64>,
    },
    Volume {
        degree: [u8; 3],
        x: Vec<f64>,
        y: Vec<f64>,
        z: Vec<f64>,
        xi: Vec<f64>,
    },
    Circle {
        center: [f64; 2],
        radius: f64,
    },
    Sphere {
        center: [f64; 3],
        radius: f64,
    },
    Rectangle {
        min: [f64; 2],
        max: [f64; 2],
    },
    Box {
        min: [f64; 3],
        max: [f64; 3],
    },
    /// `axis` 0, 1, 2 for x, y, z.
    Cylinder {
        center: [f64; 3],
        axis: u8,
        radius: f64,
    },
    Torus {
        center: [f64; 3],
        axis: u8,
        major: f64,
        minor: f64,
    },
    Halfplane {
        normal: [f64; 2],
        offset: f64,
    },
    Halfspace {
        normal: [f64; 3],
        offset: f64,
    },
    Union {
        count: u32,
    },
    Intersection {
        count: u32,
    },
    Difference {
        count: u32,
    },
    BlendUnion {
        a0: f64,
        a1: f64,
        a2: f64,
    },
    BlendIntersection {
        a0: f64,
        a1: f64,
        a2: f64,
    },
    Morph {
        t: f64,
    },
    /// Each list empty where the model file has no such field; `rotate` holds one angle (2D) or
    /// three (3D).
    Transform {
        translate: Vec<f64>,
        rotate: Vec<f64>,
        scale: Vec<f64>,
    },
    /// A named part (appended: the variants above keep their numbers).
    Part {
        name: alloc::string::String,
        hidden: bool,
    },
    /// A piecewise solid (appended): its cells and degree (2 or 3 numbers each) and its global
    /// net by columns, `x, y[, z], ξ`.
    Piecewise {
        cells: Vec<u8>,
        degree: Vec<u8>,
        columns: Vec<Vec<f64>>,
    },
    /// A HyperFun program (appended): its text and its box, if the node has one.
    Hyperfun {
        program: alloc::string::String,
        bounds: Option<[[f64; 3]; 2]>,
    },
}

const AXES: [CoordAxis; 3] = [CoordAxis::X, CoordAxis::Y, CoordAxis::Z];

fn refused(path: &str, message: &str) -> LinkError {
    LinkError::Model(ModelError::Tree(TreeError {
        path: path.into(),
        message: message.into(),
    }))
}

/// The nodes of the tree `root`, in prefix order.
pub(super) fn flatten(root: &SolidSpec) -> Result<Vec<Node>, LinkError> {
    let mut out = Vec::new();
    let mut todo = alloc::vec![root];
    while let Some(spec) = todo.pop() {
        if out.len() == MAX_NODES {
            return Err(refused(
                "solid",
                "the tree has more nodes than a model may hold",
            ));
        }
        let children = spec.children();
        let count = u32::try_from(children.len()).unwrap_or(u32::MAX);
        out.push(match spec {
            SolidSpec::Patch { degree, points } => {
                let [x, y, xi] = columns(points);
                Node::Patch {
                    degree: degree.map(byte),
                    x,
                    y,
                    xi,
                }
            }
            SolidSpec::Volume { degree, points } => {
                let [x, y, z, xi] = columns(points);
                Node::Volume {
                    degree: degree.map(byte),
                    x,
                    y,
                    z,
                    xi,
                }
            }
            SolidSpec::Esc { .. } | SolidSpec::Plasm { .. } => {
                return Err(refused(
                    "solid",
                    "a free-form model or a script is a model of its own, not a node of a tree",
                ));
            }
            SolidSpec::Hyperfun { program, bounds } => Node::Hyperfun {
                program: program.clone(),
                bounds: *bounds,
            },
            &SolidSpec::Circle { center, radius } => Node::Circle { center, radius },
            &SolidSpec::Sphere { center, radius } => Node::Sphere { center, radius },
            &SolidSpec::Rectangle { min, max } => Node::Rectangle { min, max },
            &SolidSpec::Box { min, max } => Node::Box { min, max },
            &SolidSpec::Cylinder {
                center,
                axis,
                radius,
            } => Node::Cylinder {
                center,
                axis: axis.index() as u8,
                radius,
            },
            &SolidSpec::Torus {
                center,
                axis,
                major,
                minor,
            } => Node::Torus {
                center,
                axis: axis.index() as u8,
                major,
                minor,
            },
            &SolidSpec::Halfplane { normal, offset } => Node::Halfplane { normal, offset },
            &SolidSpec::Halfspace { normal, offset } => Node::Halfspace { normal, offset },
            SolidSpec::Union { .. } => Node::Union { count },
            SolidSpec::Intersection { .. } => Node::Intersection { count },
            SolidSpec::Difference { .. } => Node::Difference { count },
            &SolidSpec::BlendUnion { a0, a1, a2, .. } => Node::BlendUnion { a0, a1, a2 },
            &SolidSpec::BlendIntersection { a0, a1, a2, .. } => {
                Node::BlendIntersection { a0, a1, a2 }
            }
            &SolidSpec::Morph { t, .. } => Node::Morph { t },
            SolidSpec::Transform {
                translate,
                rotate,
                scale,
                ..
            } => Node::Transform {
                translate: translate.clone().unwrap_or_default(),
                rotate: match rotate {
                    None => Vec::new(),
                    Some(Rotation::Angle(a)) => alloc::vec![*a],
                    Some(Rotation::Angles(a)) => a.to_vec(),
                },
                scale: scale.clone().unwrap_or_default(),
            },
            SolidSpec::Part { name, hidden, .. } => Node::Part {
                name: name.clone(),
                hidden: *hidden,
            },
            SolidSpec::Piecewise {
                cells,
                degree,
                points,
            } => {
                // Points of another length than the first are carried as the first's: the
                // reader's validation refuses the net the same (the file's reader names them).
                let width = points.first().map_or(0, Vec::len);
                if points.iter().any(|p| p.len() != width) {
                    return Err(refused(
                        "solid",
                        "a piecewise solid's points have different numbers of coordinates",
                    ));
                }
                Node::Piecewise {
                    cells: cells.iter().map(|&c| byte(c)).collect(),
                    degree: degree.iter().map(|&d| byte(d)).collect(),
                    columns: (0..width)
                        .map(|c| points.iter().map(|p| p[c]).collect())
                        .collect(),
                }
            }
        });
        // A blend or morph of another number of nodes is carried as it is; the reader takes two.
        if matches!(
            spec,
            SolidSpec::BlendUnion { .. }
                | SolidSpec::BlendIntersection { .. }
                | SolidSpec::Morph { .. }
        ) && children.len() != 2
        {
            return Err(refused("solid", "a blend or a morph takes exactly 2 nodes"));
        }
        todo.extend(children.iter().rev());
    }
    Ok(out)
}

/// An operation waiting for its children.
struct Open {
    node: Node,
    want: usize,
    children: Vec<SolidSpec>,
}

/// The tree of `nodes` (prefix order), within the caps of a model.
pub(super) fn build(nodes: Vec<Node>) -> Result<SolidSpec, LinkError> {
    if nodes.len() > MAX_NODES {
        return Err(refused(
            "solid",
            "the link's tree has more nodes than a model may hold",
        ));
    }
    let mut open: Vec<Open> = Vec::new();
    let mut root = None;
    for node in nodes {
        if root.is_some() {
            return Err(LinkError::Decode); // nodes after the whole tree
        }
        let want = match &node {
            Node::Union { count } | Node::Intersection { count } | Node::Difference { count } => {
                usize::try_from(*count).map_err(|_| LinkError::Decode)?
            }
            Node::BlendUnion { .. } | Node::BlendIntersection { .. } | Node::Morph { .. } => 2,
            Node::Transform { .. } | Node::Part { .. } => 1,
            _ => 0,
        };
        let mut done = if want == 0 {
            leaf(node)?
        } else {
            if open.len() == MAX_DEPTH {
                return Err(refused(
                    "solid",
                    "the link's tree is deeper than a model may be",
                ));
            }
            open.push(Open {
                node,
                want,
                children: Vec::new(),
            });
            continue;
        };
        // Hand the finished node to its parent, finishing every parent it completes.
        loop {
            let Some(parent) = open.last_mut() else {
                root = Some(done);
                break;
            };
            parent.children.push(done);
            if parent.children.len() < parent.want {
                break;
            }
            let Some(parent) = open.pop() else { break };
            done = operation(parent)?;
        }
    }
    match (root, open.is_empty()) {
        (Some(root), true) => Ok(root),
        _ => Err(LinkError::Decode), // the nodes end inside an operation
    }
}

fn axis(a: u8) -> Result<CoordAxis, LinkError> {
    AXES.get(usize::from(a)).copied().ok_or(LinkError::Decode)
}

fn leaf(node: Node) -> Result<SolidSpec, LinkError> {
    Ok(match node {
        Node::Patch { degree, x, y, xi } => SolidSpec::Patch {
            degree: degree.map(usize::from),
            points: rows([x, y, xi])?,
        },
        Node::Volume {
            degree,
            x,
            y,
            z,
            xi,
        } => SolidSpec::Volume {
            degree: degree.map(usize::from),
            points: rows([x, y, z, xi])?,
        },
        Node::Circle { center, radius } => SolidSpec::Circle { center, radius },
        Node::Sphere { center, radius } => SolidSpec::Sphere { center, radius },
        Node::Rectangle { min, max } => SolidSpec::Rectangle { min, max },
        Node::Box { min, max } => SolidSpec::Box { min, max },
        Node::Cylinder {
            center,
            axis: a,
            radius,
        } => SolidSpec::Cylinder {
            center,
            axis: axis(a)?,
            radius,
        },
        Node::Torus {
            center,
            axis: a,
            major,
            minor,
        } => SolidSpec::Torus {
            center,
            axis: axis(a)?,
            major,
            minor,
        },
        Node::Halfplane { normal, offset } => SolidSpec::Halfplane { normal, offset },
        Node::Halfspace { normal, offset } => SolidSpec::Halfspace { normal, offset },
        Node::Piecewise {
            cells,
            degree,
            columns,
        } => {
            // Points of any width come back as they went (validation says what is wrong).
            let len = columns.first().map_or(0, Vec::len);
            if columns.iter().any(|c| c.len() != len) {
                return Err(LinkError::Decode);
            }
            SolidSpec::Piecewise {
                cells: cells.into_iter().map(usize::from).collect(),
                degree: degree.into_iter().map(usize::from).collect(),
                points: (0..len)
                    .map(|k| columns.iter().map(|c| c[k]).collect())
                    .collect(),
            }
        }
        Node::Hyperfun { program, bounds } => SolidSpec::Hyperfun { program, bounds },
        // An operation of no children (a union of none): validation names it.
        Node::Union { .. } => SolidSpec::Union { of: Vec::new() },
        Node::Intersection { .. } => SolidSpec::Intersection { of: Vec::new() },
        Node::Difference { .. } => SolidSpec::Difference { of: Vec::new() },
        _ => return Err(LinkError::Decode),
    })
}

fn operation(open: Open) -> Result<SolidSpec, LinkError> {
    let of = open.children;
    Ok(match open.node {
        Node::Union { .. } => SolidSpec::Union { of },
        Node::Intersection { .. } => SolidSpec::Intersection { of },
        Node::Difference { .. } => SolidSpec::Difference { of },
        Node::BlendUnion { a0, a1, a2 } => SolidSpec::BlendUnion { of, a0, a1, a2 },
        Node::BlendIntersection { a0, a1, a2 } => SolidSpec::BlendIntersection { of, a0, a1, a2 },
        Node::Morph { t } => SolidSpec::Morph { of, t },
        Node::Transform {
            translate,
            rotate,
            scale,
        } => {
            let solid = Box::new(of.into_iter().next().ok_or(LinkError::Decode)?);
            let list = |v: Vec<f64>| (!v.is_empty()).then_some(v);
            let rotate = match rotate[..] {
                [] => None,
                [a] => Some(Rotation::Angle(a)),
                [x, y, z] => Some(Rotation::Angles([x, y, z])),
                _ => return Err(LinkError::Decode),
            };
            SolidSpec::Transform {
                solid,
                translate: list(translate),
                rotate,
                scale: list(scale),
            }
        }
        Node::Part { name, hidden } => SolidSpec::Part {
            solid: Box::new(of.into_iter().next().ok_or(LinkError::Decode)?),
            name,
            hidden,
        },
        _ => return Err(LinkError::Decode),
    })
}

#[cfg(test)]
mod tests {
    use super::super::{LinkError, decode_file, encode};
    use crate::model::{CoordAxis, ModelFile, Rotation, SolidSpec as S};
    use crate::solid::Solid3;
    use crate::tree::{MAX_DEPTH, MAX_NODES, ModelTree};
    use alloc::boxed::Box;
    use alloc::format;
    use alloc::string::String;
    use alloc::vec;
    use alloc::vec::Vec;
    use glam::DVec3;
    #[cfg(target_arch = "wasm32")]
    use wasm_bindgen_test::wasm_bindgen_test as test;

    fn volume_at(x: f64) -> S {
        let v = Solid3::regular(
            [3, 3, 3],
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x + 1.0, 1.0, 1.0),
            |_| 0.25,
        )
        .unwrap();
        ModelFile::from_solid3(&v).solid
    }

    /// A tree with every kind of 3D node, and awkward numbers.
    fn every_kind() -> S {
        S::Difference {
            of: vec![
                S::BlendUnion {
                    of: vec![
                        volume_at(0.123_456_789_012_345_6),
                        S::Part {
                            solid: Box::new(S::Sphere {
                                center: [0.1, -0.2, f64::MIN_POSITIVE],
                                radius: 1.0 / 3.0,
                            }),
                            name: "Ball \u{2713} \"quoted\"".into(),
                            hidden: true,
                        },
                    ],
                    a0: 0.5,
                    a1: -1.25,
                    a2: 2.0,
                },
                S::Transform {
                    solid: Box::new(S::Morph {
                        of: vec![
                            S::Torus {
                                center: [0.0, 0.0, 1.0],
                                axis: CoordAxis::Y,
                                major: 1.5,
                                minor: 0.25,
                            },
                            S::Cylinder {
                                center: [0.0; 3],
                                axis: CoordAxis::Z,
                                radius: 0.5,
                            },
                        ],
                        t: 0.3,
                    }),
                    translate: Some(vec![1.0, 2.0, 3.0]),
                    rotate: Some(Rotation::Angles([10.0, 20.0, -30.0])),
                    scale: None,
                },
                S::Intersection {
                    of: vec![
                        S::Box {
                            min: [-1.0; 3],
                            max: [1.0; 3],
                        },
                        S::Halfspace {
                            normal: [0.0, 0.0, 1.0],
                            offset: -0.0,
                        },
                        S::BlendIntersection {
                            of: vec![
                                S::Sphere {
                                    center: [0.0; 3],
                                    radius: 2.0,
                                },
                                S::Union {
                                    of: vec![
                                        S::Sphere {
                                            center: [1.0; 3],
                                            radius: 1.0,
                                        },
                                        S::Sphere {
                                            center: [-1.0; 3],
                                            radius: 1.0,
                                        },
                                    ],
                                },
                            ],
                            a0: 1.0,
                            a1: 1.0,
                            a2: 1.0,
                        },
                    ],
                },
            ],
        }
    }

    #[test]
    fn trees_round_trip_through_links_bit_exact() {
        for spec in [
            every_kind(),
            S::Transform {
                solid: Box::new(S::Union {
                    of: vec![
                        S::Part {
                            solid: Box::new(S::Circle {
                                center: [0.0, 0.5],
                                radius: 1.0,
                            }),
                            name: String::new(),
                            hidden: false,
                        },
                        S::Rectangle {
                            min: [0.0, 0.0],
                            max: [2.0, 1.0],
                        },
                        S::Halfplane {
                            normal: [1.0, 1.0],
                            offset: 0.5,
                        },
                    ],
                }),
                translate: None,
                rotate: Some(Rotation::Angle(45.0)),
                scale: Some(vec![2.0, -1.0]),
            },
        ] {
            let file = ModelFile::from_spec(spec);
            file.to_tree().unwrap();
            let link = encode(&file).unwrap();
            let back = decode_file(&link).unwrap();
            assert_eq!(back, file);
            assert_eq!(format!("{:?}", back.solid), format!("{:?}", file.solid));
        }
    }

    #[test]
    fn piecewise_solids_round_trip_through_links_alone_and_in_trees() {
        use alloc::string::ToString;
        let mut rng = crate::testutil::Rng::new(4);
        let patch = S::Piecewise {
            cells: vec![2, 3],
            degree: vec![1, 2],
            points: (0..21)
                .map(|k| {
                    vec![
                        f64::from(k / 7),
                        f64::from(k % 7) / 3.0,
                        rng.range(-1.0, 1.0),
                    ]
                })
                .collect(),
        };
        let volume = crate::testutil::random_piecewise3(&mut rng, true);
        for spec in [
            patch.clone(),
            volume.clone(),
            S::Union {
                of: vec![
                    volume,
                    S::Sphere {
                        center: [0.0; 3],
                        radius: 0.5,
                    },
                ],
            },
        ] {
            let file = ModelFile::from_spec(spec);
            file.to_tree().unwrap();
            let link = encode(&file).unwrap();
            assert_eq!(decode_file(&link).unwrap(), file);
        }
        // Columns of different lengths are not a net.
        let broken = link_of(&[super::Node::Piecewise {
            cells: vec![1, 1],
            degree: vec![1, 1],
            columns: vec![vec![0.0; 4], vec![0.0; 4], vec![0.0; 3]],
        }]);
        assert!(decode_file(&broken).is_err());
        // A net of the wrong count travels and is refused when read, with what is wrong.
        let S::Piecewise {
            cells,
            degree,
            mut points,
        } = patch
        else {
            unreachable!()
        };
        points.pop();
        let file = ModelFile::from_spec(S::Piecewise {
            cells,
            degree,
            points,
        });
        let e = decode_file(&encode(&file).unwrap()).map(|f| f.to_tree().map(drop));
        let message = match e {
            Ok(Err(e)) => e.to_string(),
            Err(e) => e.to_string(),
            Ok(Ok(())) => panic!("a net of 20 points for 21 was read"),
        };
        assert!(message.contains("20 control points"), "{message}");
    }

    #[test]
    fn a_tree_of_twenty_default_volumes_makes_a_short_link() {
        let leaves: Vec<S> = (0..20).map(|i| volume_at(f64::from(i) * 1.5)).collect();
        let file = ModelFile::from_spec(S::Union { of: leaves });
        let ModelTree::Space(tree) = file.to_tree().unwrap() else {
            panic!("3D")
        };
        assert_eq!(tree.bezier_count(), 20);
        let link = encode(&file).unwrap();
        assert!(link.len() < 4000, "{} characters", link.len());
        assert_eq!(decode_file(&link).unwrap(), file);
    }

    /// The fragment of `nodes` as an encoder would write it.
    fn link_of(nodes: &[super::Node]) -> alloc::string::String {
        use base64::Engine as _;
        let mut bytes = postcard::to_allocvec(&4u32).unwrap(); // the variant
        bytes.extend(postcard::to_allocvec(nodes).unwrap());
        let packed = miniz_oxide::deflate::compress_to_vec(&bytes, 10);
        format!(
            "#v1.{}",
            base64::engine::general_purpose::URL_SAFE_NO_PAD.encode(packed)
        )
    }

    #[test]
    fn deep_wide_and_broken_trees_are_refused_before_they_are_built() {
        use super::Node;
        let sphere = || Node::Sphere {
            center: [0.0; 3],
            radius: 1.0,
        };
        let transform = || Node::Transform {
            translate: Vec::new(),
            rotate: Vec::new(),
            scale: Vec::new(),
        };
        // Far deeper than a model may be: refused at the cap, with no recursion.
        let mut deep: Vec<Node> = (0..5000).map(|_| transform()).collect();
        deep.push(sphere());
        let e = decode_file(&link_of(&deep)).unwrap_err();
        assert!(matches!(e, LinkError::Model(_)), "{e}");
        let mut ok: Vec<Node> = (0..MAX_DEPTH - 1).map(|_| transform()).collect();
        ok.push(sphere());
        decode_file(&link_of(&ok)).unwrap().to_tree().unwrap();
        // Wider than a model may be.
        let mut wide = vec![Node::Union {
            count: MAX_NODES as u32,
        }];
        wide.extend((0..MAX_NODES).map(|_| sphere()));
        assert!(matches!(
            decode_file(&link_of(&wide)),
            Err(LinkError::Model(_))
        ));
        // An operation left open, nodes after the tree, a bad axis, a rotation of two angles.
        for broken in [
            vec![Node::Union { count: 3 }, sphere(), sphere()],
            vec![sphere(), sphere()],
            vec![Node::Cylinder {
                center: [0.0; 3],
                axis: 3,
                radius: 1.0,
            }],
            vec![
                Node::Transform {
                    translate: Vec::new(),
                    rotate: vec![1.0, 2.0],
                    scale: Vec::new(),
                },
                sphere(),
            ],
            vec![],
        ] {
            assert_eq!(decode_file(&link_of(&broken)), Err(LinkError::Decode));
        }
        // A union of none decodes and is refused by validation, with its path.
        let none = decode_file(&link_of(&[Node::Union { count: 0 }])).unwrap();
        assert!(none.to_tree().is_err());
    }
}

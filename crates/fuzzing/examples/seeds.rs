//! Writes the seed corpora, `fuzz/seeds/<target>/`, from the project's own data: the presets' and
//! examples' links and model files, the core's test meshes, the paper's scripts, and a few nets
//! spelled in the byte layout of the geometry targets. Run it again after a format change:
//!
//! ```sh
//! cargo run -p bezsolid-fuzzing --example seeds
//! ```

use std::path::{Path, PathBuf};

use base64::Engine as _;
use bezsolid_core::esc::Example;
use bezsolid_core::esc::Op;
use bezsolid_core::link;
use bezsolid_core::model::{EscOperand, MeshSpec, ModelFile, ModelSolid};
use bezsolid_core::presets::Preset;
use bezsolid_plasm::scripts;

fn main() -> std::io::Result<()> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds");
    let write = |target: &str, name: &str, bytes: &[u8]| -> std::io::Result<()> {
        let dir = root.join(target);
        std::fs::create_dir_all(&dir)?;
        std::fs::write(dir.join(name), bytes)
    };

    let mut models: Vec<(String, ModelFile)> = Preset::ALL
        .iter()
        .map(|p| {
            let file = match p.solid() {
                ModelSolid::Patch(s) => ModelFile::from_solid2(&s),
                ModelSolid::Volume(s) => ModelFile::from_solid3(&s),
            };
            (format!("preset-{}", p.name()), file)
        })
        .collect();
    let mut mapped = bezsolid_core::Solid2::fig9();
    mapped
        .set_point([1, 1], glam::DVec2::new(0.7, 0.2))
        .expect("a point of fig9");
    models.push(("fig9-moved".into(), ModelFile::from_solid2(&mapped)));
    models.push((
        "esc-blob-minus-torus".into(),
        ModelFile::from_esc(
            Some(Op::Difference),
            vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand::example(Example::Torus, [0.25, -0.5, 0.125]),
            ],
        ),
    ));
    models.push((
        "esc-tetra".into(),
        ModelFile::from_esc(
            None,
            vec![EscOperand {
                example: None,
                mesh: Some(MeshSpec {
                    positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                    triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                }),
                offset: [0.0; 3],
                ..EscOperand::default()
            }],
        ),
    ));
    models.push((
        "esc-expression".into(),
        ModelFile::from_spec(bezsolid_core::model::SolidSpec::Esc {
            operation: None,
            expression: Some("!(A | wing) - C & A".into()),
            operands: vec![
                EscOperand::example(Example::Blob, [0.0; 3]),
                EscOperand {
                    name: Some("wing".into()),
                    rotate: Some([0.0, 70.0, 20.0]),
                    scale: Some([0.8, 0.8, -1.4]),
                    ..EscOperand::example(Example::Torus, [0.2, 0.0, 0.3])
                },
                EscOperand {
                    crease: Some(40.0),
                    mesh: Some(MeshSpec {
                        positions: vec![
                            [0.0; 3],
                            [1.0, 0.0, 0.0],
                            [0.0, 1.0, 0.0],
                            [0.0, 0.0, 1.0],
                        ],
                        triangles: vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
                    }),
                    ..EscOperand::default()
                },
            ],
        }),
    ));
    models.push((
        "esc-complement".into(),
        ModelFile::from_spec(bezsolid_core::model::SolidSpec::Esc {
            operation: Some("complement".into()),
            expression: None,
            operands: vec![EscOperand::example(Example::Icosphere, [0.0; 3])],
        }),
    ));
    // Piecewise solids: a patch of 2 × 2 quadratic cells, regular, and a volume of 2 × 1 × 1
    // linear-by-quadratic cells with a point moved.
    let patch_points = (0..25)
        .map(|k| {
            let (i, j) = (k / 5, k % 5);
            let xi = if (1..4).contains(&i) && (1..4).contains(&j) {
                1.0
            } else {
                -0.5
            };
            vec![f64::from(i) / 4.0, f64::from(j) / 4.0, xi]
        })
        .collect();
    models.push((
        "piecewise-patch".into(),
        ModelFile::from_spec(bezsolid_core::model::SolidSpec::Piecewise {
            cells: vec![2, 2],
            degree: vec![2, 2],
            points: patch_points,
        }),
    ));
    let mut volume_points: Vec<Vec<f64>> = (0..27)
        .map(|k| {
            let (i, j, l) = (k / 9, (k / 3) % 3, k % 3);
            let xi = if (i, j, l) == (1, 1, 1) { 1.0 } else { -0.3 };
            vec![
                f64::from(i) / 2.0,
                f64::from(j) / 2.0,
                f64::from(l) / 2.0,
                xi,
            ]
        })
        .collect();
    volume_points[13][0] += 0.1;
    models.push((
        "piecewise-volume-moved".into(),
        ModelFile::from_spec(bezsolid_core::model::SolidSpec::Piecewise {
            cells: vec![2, 1, 1],
            degree: vec![1, 2, 2],
            points: volume_points,
        }),
    ));
    let example = scripts::example("4.1").expect("the paper's example 4.1");
    models.push(("plasm-4.1".into(), ModelFile::from_plasm(&example.source())));

    for (name, file) in &models {
        let text = link::encode(file).expect("a seed model fits in a link");
        write("link", &format!("{name}.link"), text.as_bytes())?;
        let json = serde_json::to_string_pretty(file).expect("a model file writes");
        write("model", &format!("{name}.bsolid.json"), json.as_bytes())?;
    }
    // The link target's byte modes: 0x01 then the deflated data, 0x00 then the inflated data.
    let fig9 = link::encode(&models[0].1).expect("fig9's link");
    let deflated = base64::engine::general_purpose::URL_SAFE_NO_PAD
        .decode(&fig9["#v1.".len()..])
        .expect("base64url");
    let inflated = miniz_oxide::inflate::decompress_to_vec(&deflated).expect("it inflates");
    write(
        "link",
        "fig9-deflated.bin",
        &[&[1u8][..], &deflated].concat(),
    )?;
    write(
        "link",
        "fig9-inflated.bin",
        &[&[0u8][..], &inflated].concat(),
    )?;
    write(
        "link",
        "fig9-address.link",
        format!("http://127.0.0.1:8080/?backend=webgl2{fig9}").as_bytes(),
    )?;

    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("../core/tests/fixtures/mesh");
    for name in ["cube.obj", "tetra.stl", "tetra_ascii.stl", "open.obj"] {
        write("mesh_import", name, &std::fs::read(fixtures.join(name))?)?;
    }
    write(
        "mesh_import",
        "tetra-normals.obj",
        b"# A tetrahedron with a normal at every corner, indices relative and absolute.\n\
          v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
          vn 0 0 -1\nvn 0 -1 0\nvn -1 0 0\nvn 0.577 0.577 0.577\n\
          f 1//1 3//1 2//1\nf -4//2 -3//2 -1//2\nf 1//3 4//3 3//3\nf 2//4 3//4 4//4\n",
    )?;
    write(
        "mesh_import",
        "tetra.ply",
        b"ply\nformat ascii 1.0\ncomment a tetrahedron with normals\nelement vertex 4\n\
          property float x\nproperty float y\nproperty float z\n\
          property float nx\nproperty float ny\nproperty float nz\n\
          element face 4\nproperty list uchar int vertex_indices\nend_header\n\
          0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n\
          3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    )?;
    let cube = bezsolid_core::esc::Example::Icosphere.mesh();
    write(
        "mesh_import",
        "icosphere.ply",
        &bezsolid_core::mesh::Format::Ply.write(&cube),
    )?;

    for s in [
        scripts::S3_1,
        scripts::S3_2,
        scripts::S3_3,
        scripts::S4_1,
        scripts::S4_2,
        scripts::S4_3,
        scripts::S4_4,
        scripts::S4_5,
        scripts::S4_6,
        scripts::S4_7,
        scripts::S4_7_BEZIER_GRID,
        scripts::S4_8,
    ] {
        write(
            "plasm",
            &format!("script-{}.psm", s.number),
            s.text.as_bytes(),
        )?;
    }
    for e in scripts::EXAMPLES {
        write(
            "plasm",
            &format!("example-{}.psm", e.id),
            e.source().as_bytes(),
        )?;
    }

    // The geometry targets read a net as: a degree byte per axis (b < 240: 1 + b % 6), the box
    // side's scale (below 16; 6 and up: 1), per axis an origin (a signed byte, a scale), ξ's scale,
    // ξ's mode (below 4; 0: one value with a sign per point), one byte of ξ per point, the number
    // of edits (below 12), each two indices (two bytes each), an operation (below 9) and its bytes.
    // Zeros past the end: degree 1, a unit box at the origin, ξ = 10⁻⁹ of one sign, no edit.
    let bicubic_bump = net(
        &[2, 2],
        &[0, 1, 0, 1],
        [-64, -64, -64, -64, 64, -64, -64, -64, -64],
        3,
        &[],
    );
    // The bump with point 5 mirrored through point 7: the net folds over.
    let folded = net(
        &[2, 2],
        &[0, 1, 0, 1],
        [-64, -64, -64, -64, 64, -64, -64, -64, -64],
        1,
        &[&[0, 5, 0, 7, 3]],
    );
    // Point 0 onto point 8, and 3 onto the line through 1 and 7.
    let degenerate = net(
        &[1, 1, 1],
        &[0, 1, 0, 1, 0, 1],
        [-64, -64, -64, -64, -64, -64, -64, 64],
        1,
        &[&[0, 0, 0, 7, 1], &[0, 3, 0, 1, 2, 0, 7, 64]],
    );
    let volume = net(
        &[1, 1, 1],
        &[0, 1, 0, 1, 0, 1],
        [-64, -64, -64, -64, -64, -64, -64, 64],
        1,
        &[],
    );
    // Queries: 4 (below 4 + 1), inside (mode 4, three units), at a control point (mode 0),
    // outside (mode 2), anywhere (mode 1, eight bytes per coordinate).
    let queries = [
        &[3u8, 4, 128, 128, 128, 0, 0, 3, 2, 0, 0, 0, 0, 0, 128][..],
        &[
            1, 0x40, 0x08, 0, 0, 0, 0, 0, 0, 0x40, 0x08, 0, 0, 0, 0, 0, 0, 0, 0,
        ],
    ]
    .concat();
    for (name, bytes) in [
        ("patch-bump", [&[0u8][..], &bicubic_bump, &queries].concat()),
        ("patch-folded", [&[0u8][..], &folded, &queries].concat()),
        ("volume", [&[1u8][..], &volume, &queries].concat()),
        (
            "volume-degenerate",
            [&[1u8][..], &degenerate, &queries].concat(),
        ),
    ] {
        write("eval", &format!("{name}.bin"), &bytes)?;
    }
    // Contours and meshes: a resolution (2 + below 15; 1 + below 8) and an accuracy (below 4).
    write(
        "contour",
        "bump.bin",
        &[&[6u8, 2][..], &bicubic_bump].concat(),
    )?;
    write("contour", "folded.bin", &[&[6u8, 2][..], &folded].concat())?;
    write("mesh", "volume.bin", &[&[5u8, 2][..], &volume].concat())?;
    write(
        "mesh",
        "degenerate.bin",
        &[&[5u8, 2][..], &degenerate].concat(),
    )?;
    println!("wrote the seeds under {}", root.display());
    Ok(())
}

/// A net in the geometry targets' layout: degrees as written in a model file, the scale bytes of
/// the box, ξ's mode and values (`xi`, one byte each, as `i8`/128 of the unit scale) and edits.
fn net<const N: usize>(
    degree: &[u8],
    origin: &[u8],
    xi: [i8; N],
    mode: u8,
    edits: &[&[u8]],
) -> Vec<u8> {
    let mut out: Vec<u8> = degree.iter().map(|d| d - 1).collect();
    out.push(6);
    out.extend_from_slice(origin);
    out.extend([6, mode]);
    out.extend(xi.map(|x| x as u8));
    // Missing ξ bytes are zeros: the seed's net may have more points than it spells.
    let points: usize = degree.iter().map(|&d| usize::from(d) + 1).product();
    out.extend(std::iter::repeat_n(0, points.saturating_sub(N)));
    out.push(edits.len() as u8);
    for e in edits {
        out.extend_from_slice(e);
    }
    out
}

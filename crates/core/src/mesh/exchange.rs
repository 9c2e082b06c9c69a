//! Mesh files for the tools people already use: every format a mesh is exported in
//! ([`ExportFormat`]), the plain ones of [`Format`] and two containers, 3MF for slicers and GLB for
//! viewers and the web.
//!
//! - **3MF** (the 3MF Consortium's core specification): an OPC zip holding `[Content_Types].xml`,
//!   `_rels/.rels` and the model part `3D/3dmodel.model`, in millimetres (one model unit is one
//!   millimetre), Z up as the model is, with the model's title and the application in its metadata.
//! - **GLB** (glTF 2.0 binary): positions, unit normals and `u32` indices in one buffer, in
//!   metres and +Y up as glTF asks: a model point `(x, y, z)` in millimetres is `(x, z, −y) / 1000`
//!   (a rotation about x, so the winding and the outward normals are kept), the generator named.
//!
//! Writing the containers takes the `exchange` feature (the `zip` and `gltf-json` crates, `std`);
//! without it [`ExportFormat::write`] says so for those two.

use alloc::string::String;
use alloc::vec::Vec;
use core::fmt;
use core::str::FromStr;

use super::{Format, Mesh};

/// A format a mesh is exported in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum ExportFormat {
    /// STL (binary).
    Stl,
    /// Wavefront OBJ.
    Obj,
    /// PLY (binary little-endian).
    Ply,
    /// 3MF, for slicers: millimetres, Z up.
    #[cfg_attr(feature = "serde", serde(rename = "3mf"))]
    ThreeMf,
    /// GLB (glTF 2.0 binary), for viewers and the web: metres, +Y up.
    Glb,
}

impl ExportFormat {
    /// Every format.
    pub const ALL: [Self; 5] = [Self::Stl, Self::Obj, Self::Ply, Self::ThreeMf, Self::Glb];

    /// The file name extension, lower case and without the dot.
    #[must_use]
    pub const fn extension(self) -> &'static str {
        match self {
            Self::Stl => "stl",
            Self::Obj => "obj",
            Self::Ply => "ply",
            Self::ThreeMf => "3mf",
            Self::Glb => "glb",
        }
    }

    /// The media type of a file of this format.
    #[must_use]
    pub const fn media_type(self) -> &'static str {
        match self {
            Self::ThreeMf => "model/3mf",
            Self::Glb => "model/gltf-binary",
            Self::Stl => Format::Stl.media_type(),
            Self::Obj => Format::Obj.media_type(),
            Self::Ply => Format::Ply.media_type(),
        }
    }

    /// The plain format this is, `None` for a container.
    #[must_use]
    pub const fn plain(self) -> Option<Format> {
        match self {
            Self::Stl => Some(Format::Stl),
            Self::Obj => Some(Format::Obj),
            Self::Ply => Some(Format::Ply),
            Self::ThreeMf | Self::Glb => None,
        }
    }

    /// The format of a file named `path`, by its extension (any case); `None` for another.
    #[must_use]
    pub fn of_path(path: &str) -> Option<Self> {
        let (_, ext) = path.rsplit_once('.')?;
        ext.parse().ok()
    }

    /// The file of `mesh` in this format; `title` names the model where the format keeps a name
    /// (3MF's `Title` metadata, the GLB's mesh).
    ///
    /// # Errors
    ///
    /// [`ExportError`]: a container without the `exchange` feature, or one the writer could not
    /// make (a mesh past the format's size limits).
    pub fn write(self, mesh: &Mesh, title: &str) -> Result<Vec<u8>, ExportError> {
        match self {
            Self::Stl => Ok(Format::Stl.write(mesh)),
            Self::Obj => Ok(Format::Obj.write(mesh)),
            Self::Ply => Ok(Format::Ply.write(mesh)),
            #[cfg(feature = "exchange")]
            Self::ThreeMf => containers::write_3mf(mesh, title),
            #[cfg(feature = "exchange")]
            Self::Glb => containers::write_glb(mesh, title),
            #[cfg(not(feature = "exchange"))]
            Self::ThreeMf | Self::Glb => {
                let _ = title;
                Err(ExportError::Unsupported(self))
            }
        }
    }
}

impl From<Format> for ExportFormat {
    fn from(format: Format) -> Self {
        match format {
            Format::Stl => Self::Stl,
            Format::Obj => Self::Obj,
            Format::Ply => Self::Ply,
        }
    }
}

impl fmt::Display for ExportFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

impl FromStr for ExportFormat {
    type Err = ExportError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|f| f.extension().eq_ignore_ascii_case(s))
            .ok_or_else(|| ExportError::Unknown(s.into()))
    }
}

/// Why a mesh file could not be made.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ExportError {
    /// Not a format's name.
    Unknown(String),
    /// A container format in a build without the `exchange` feature.
    Unsupported(ExportFormat),
    /// The container's writer failed (a mesh past the format's size limits).
    Container(String),
}

impl fmt::Display for ExportError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Unknown(s) => write!(
                f,
                "unknown mesh format {s:?}: the formats are stl, obj, ply, 3mf and glb"
            ),
            Self::Unsupported(format) => write!(
                f,
                "{format} files are written by builds with the `exchange` feature"
            ),
            Self::Container(e) => write!(f, "the file could not be written: {e}"),
        }
    }
}

impl core::error::Error for ExportError {}

/// The titles, vertices and triangles a container keeps, checked for what the formats forbid.
#[cfg(feature = "exchange")]
mod containers {
    use alloc::format;
    use alloc::string::{String, ToString};
    use alloc::vec;
    use alloc::vec::Vec;
    use core::fmt::Write as _;
    use std::io::{Cursor, Write as _};

    use glam::DVec3;
    use gltf_json as json;
    use json::validation::{Checked::Valid, USize64};

    use super::ExportError;
    use crate::mesh::Mesh;

    /// The application named in the files' metadata.
    const GENERATOR: &str = concat!("bezsolid ", env!("CARGO_PKG_VERSION"));

    fn container(e: impl core::fmt::Display) -> ExportError {
        ExportError::Container(e.to_string())
    }

    /// The triangles whose three corners are distinct vertices of the mesh (a triangle with a
    /// repeated or missing corner is no face: 3MF forbids it, glTF draws nothing of it).
    fn faces(mesh: &Mesh) -> impl Iterator<Item = [u32; 3]> + '_ {
        let n = mesh.positions.len();
        mesh.triangles.iter().copied().filter(move |&[a, b, c]| {
            a != b && b != c && a != c && [a, b, c].iter().all(|&i| (i as usize) < n)
        })
    }

    /// `text` with the five XML special characters escaped.
    fn xml_escaped(text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        for c in text.chars() {
            match c {
                '&' => out.push_str("&amp;"),
                '<' => out.push_str("&lt;"),
                '>' => out.push_str("&gt;"),
                '"' => out.push_str("&quot;"),
                '\'' => out.push_str("&apos;"),
                // XML 1.0 has no other control characters.
                c if c.is_control() && !matches!(c, '\t' | '\n' | '\r') => {}
                c => out.push(c),
            }
        }
        out
    }

    const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">
  <Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>
  <Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>
</Types>
"#;

    const RELATIONSHIPS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">
  <Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/>
</Relationships>
"#;

    /// The 3MF model part: one object, its mesh in millimetres.
    fn model_part(mesh: &Mesh, title: &str) -> String {
        let title = xml_escaped(if title.is_empty() { "bezsolid" } else { title });
        let mut xml = String::with_capacity(64 * (mesh.positions.len() + mesh.triangles.len()));
        let _ = write!(
            xml,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
             <model unit=\"millimeter\" xml:lang=\"en-US\" \
             xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n  \
             <metadata name=\"Title\">{title}</metadata>\n  \
             <metadata name=\"Application\">{GENERATOR}</metadata>\n  \
             <metadata name=\"Description\">One model unit is one millimetre; Z is up.</metadata>\n  \
             <resources>\n    <object id=\"1\" type=\"model\">\n      <mesh>\n        <vertices>\n"
        );
        for p in &mesh.positions {
            // Rust writes the shortest decimal that reads back exactly, never an exponent.
            let _ = writeln!(
                xml,
                "          <vertex x=\"{}\" y=\"{}\" z=\"{}\"/>",
                p.x, p.y, p.z
            );
        }
        xml.push_str("        </vertices>\n        <triangles>\n");
        for [a, b, c] in faces(mesh) {
            let _ = writeln!(
                xml,
                "          <triangle v1=\"{a}\" v2=\"{b}\" v3=\"{c}\"/>"
            );
        }
        xml.push_str(
            "        </triangles>\n      </mesh>\n    </object>\n  </resources>\n  \
             <build>\n    <item objectid=\"1\"/>\n  </build>\n</model>\n",
        );
        xml
    }

    /// The 3MF package of `mesh`.
    pub(super) fn write_3mf(mesh: &Mesh, title: &str) -> Result<Vec<u8>, ExportError> {
        if mesh.positions.iter().any(|p| !p.is_finite()) {
            return Err(ExportError::Container(
                "a vertex is not finite, which 3MF cannot hold".into(),
            ));
        }
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        let parts = [
            ("[Content_Types].xml", CONTENT_TYPES.to_string()),
            ("_rels/.rels", RELATIONSHIPS.to_string()),
            ("3D/3dmodel.model", model_part(mesh, title)),
        ];
        for (name, text) in parts {
            zip.start_file(name, options).map_err(container)?;
            zip.write_all(text.as_bytes()).map_err(container)?;
        }
        Ok(zip.finish().map_err(container)?.into_inner())
    }

    /// glTF's frame of a model point: metres, +Y up.
    fn to_gltf(p: DVec3, scale: f64) -> [f32; 3] {
        [
            (p.x * scale) as f32,
            (p.z * scale) as f32,
            (-p.y * scale) as f32,
        ]
    }

    /// Unit normals for every vertex: the mesh's own where they are unit vectors, else the
    /// area-weighted normal of the faces around the vertex (+Y where there is none).
    fn unit_normals(mesh: &Mesh) -> Vec<DVec3> {
        let mut from_faces = vec![DVec3::ZERO; mesh.positions.len()];
        for [a, b, c] in faces(mesh) {
            let [pa, pb, pc] = [a, b, c].map(|i| mesh.positions[i as usize]);
            let n = (pb - pa).cross(pc - pa);
            for i in [a, b, c] {
                from_faces[i as usize] += n;
            }
        }
        (0..mesh.positions.len())
            .map(|k| {
                let own = mesh.normals.get(k).copied().unwrap_or(DVec3::ZERO);
                own.try_normalize()
                    .or_else(|| from_faces[k].try_normalize())
                    .unwrap_or(DVec3::Z)
            })
            .collect()
    }

    /// The GLB file of `mesh`.
    pub(super) fn write_glb(mesh: &Mesh, title: &str) -> Result<Vec<u8>, ExportError> {
        let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|&p| to_gltf(p, 1e-3)).collect();
        if positions.iter().flatten().any(|c| !c.is_finite()) {
            return Err(ExportError::Container(
                "a vertex is not finite in single precision, which glTF cannot hold".into(),
            ));
        }
        // A rotation: normals turn as the points do (and stay unit length).
        let normals: Vec<[f32; 3]> = unit_normals(mesh)
            .into_iter()
            .map(|n| {
                let [x, y, z] = to_gltf(n, 1.0);
                let len = (x * x + y * y + z * z).sqrt();
                [x / len, y / len, z / len]
            })
            .collect();
        let indices: Vec<u32> = faces(mesh).flatten().collect();
        let mut bin = Vec::with_capacity(4 * (6 * positions.len() + indices.len()));
        for v in positions.iter().chain(&normals) {
            for c in v {
                bin.extend_from_slice(&c.to_le_bytes());
            }
        }
        for i in &indices {
            bin.extend_from_slice(&i.to_le_bytes());
        }
        let (min, max) = positions.iter().fold(
            ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]),
            |(lo, hi), p| {
                (
                    core::array::from_fn(|k| lo[k].min(p[k])),
                    core::array::from_fn(|k| hi[k].max(p[k])),
                )
            },
        );
        let vec3_len = 12 * positions.len();

        let mut root = json::Root::default();
        root.asset.generator = Some(GENERATOR.into());
        let buffer = root.push(json::Buffer {
            byte_length: USize64::from(bin.len()),
            name: None,
            uri: None,
            extensions: Default::default(),
            extras: Default::default(),
        });
        let view = |offset: usize, length: usize, target| json::buffer::View {
            buffer,
            byte_length: USize64::from(length),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            name: None,
            target: Some(Valid(target)),
            extensions: Default::default(),
            extras: Default::default(),
        };
        use json::buffer::Target::{ArrayBuffer, ElementArrayBuffer};
        let views = [
            view(0, vec3_len, ArrayBuffer),
            view(vec3_len, vec3_len, ArrayBuffer),
            view(2 * vec3_len, 4 * indices.len(), ElementArrayBuffer),
        ];
        let [pv, nv, iv] = views.map(|v| root.push(v));
        use json::accessor::{ComponentType, GenericComponentType, Type};
        let accessor =
            |view, count: usize, component, kind, bounds: Option<([f32; 3], [f32; 3])>| {
                json::Accessor {
                    buffer_view: Some(view),
                    byte_offset: None,
                    count: USize64::from(count),
                    component_type: Valid(GenericComponentType(component)),
                    type_: Valid(kind),
                    min: bounds.map(|(lo, _)| json::Value::from(lo.to_vec())),
                    max: bounds.map(|(_, hi)| json::Value::from(hi.to_vec())),
                    name: None,
                    normalized: false,
                    sparse: None,
                    extensions: Default::default(),
                    extras: Default::default(),
                }
            };
        let bounds = (!positions.is_empty()).then_some((min, max));
        let position = root.push(accessor(
            pv,
            positions.len(),
            ComponentType::F32,
            Type::Vec3,
            bounds,
        ));
        let normal = root.push(accessor(
            nv,
            normals.len(),
            ComponentType::F32,
            Type::Vec3,
            None,
        ));
        let index = root.push(accessor(
            iv,
            indices.len(),
            ComponentType::U32,
            Type::Scalar,
            None,
        ));
        let primitive = json::mesh::Primitive {
            attributes: [
                (Valid(json::mesh::Semantic::Positions), position),
                (Valid(json::mesh::Semantic::Normals), normal),
            ]
            .into(),
            indices: Some(index),
            material: None,
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
            extensions: Default::default(),
            extras: Default::default(),
        };
        let gltf_mesh = root.push(json::Mesh {
            primitives: vec![primitive],
            weights: None,
            name: (!title.is_empty()).then(|| title.into()),
            extensions: Default::default(),
            extras: Default::default(),
        });
        let node = root.push(json::Node {
            mesh: Some(gltf_mesh),
            ..Default::default()
        });
        let scene = root.push(json::Scene {
            nodes: vec![node],
            name: None,
            extensions: Default::default(),
            extras: Default::default(),
        });
        root.scene = Some(scene);
        let mut text = json::serialize::to_vec(&root).map_err(container)?;
        // Chunks are 4-byte aligned: JSON padded with spaces, the buffer with zeros.
        text.resize(text.len().next_multiple_of(4), b' ');
        bin.resize(bin.len().next_multiple_of(4), 0);
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let length = |n: usize| {
            u32::try_from(n).map_err(|_| container(format!("{n} bytes is past GLB's 4 GiB")))
        };
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&length(total)?.to_le_bytes());
        out.extend_from_slice(&length(text.len())?.to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&length(bin.len())?.to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        Ok(out)
    }
}

#[cfg(test)]
#[cfg(feature = "exchange")]
mod tests {
    use super::*;
    use crate::mesh::tests::test_mesh;
    use alloc::string::ToString;
    use alloc::vec;
    use glam::DVec3;
    use std::io::Read;

    /// The files of the 3MF package by name, unzipped.
    fn unzip(bytes: &[u8]) -> std::collections::HashMap<String, String> {
        let mut archive = zip::ZipArchive::new(std::io::Cursor::new(bytes)).unwrap();
        (0..archive.len())
            .map(|k| {
                let mut file = archive.by_index(k).unwrap();
                let mut text = String::new();
                file.read_to_string(&mut text).unwrap();
                (file.name().unwrap().to_string(), text)
            })
            .collect()
    }

    /// A 3MF of a closed mesh read back: the OPC parts, the model in millimetres with its title,
    /// every vertex at the mesh's coordinates and every triangle its corners.
    #[test]
    fn a_3mf_package_reads_back_as_the_mesh() {
        let mesh = test_mesh();
        let bytes = ExportFormat::ThreeMf
            .write(&mesh, "Fish & <chips>")
            .unwrap();
        assert_eq!(&bytes[..2], b"PK");
        let parts = unzip(&bytes);
        let types = roxmltree::Document::parse(&parts["[Content_Types].xml"]).unwrap();
        assert!(
            types
                .descendants()
                .any(|n| n.attribute("Extension") == Some("model")
                    && n.attribute("ContentType")
                        == Some("application/vnd.ms-package.3dmanufacturing-3dmodel+xml"))
        );
        let rels = roxmltree::Document::parse(&parts["_rels/.rels"]).unwrap();
        assert!(
            rels.descendants()
                .any(|n| n.attribute("Target") == Some("/3D/3dmodel.model")
                    && n.attribute("Type")
                        == Some("http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"))
        );
        let model = roxmltree::Document::parse(&parts["3D/3dmodel.model"]).unwrap();
        let root = model.root_element();
        assert_eq!(root.attribute("unit"), Some("millimeter"));
        let title = root
            .children()
            .find(|n| n.attribute("name") == Some("Title"))
            .and_then(|n| n.text());
        assert_eq!(title, Some("Fish & <chips>"));
        let number = |n: roxmltree::Node<'_, '_>, a: &str| -> f64 {
            n.attribute(a).unwrap().parse().unwrap()
        };
        let vertices: Vec<DVec3> = model
            .descendants()
            .filter(|n| n.has_tag_name("vertex"))
            .map(|n| DVec3::new(number(n, "x"), number(n, "y"), number(n, "z")))
            .collect();
        assert_eq!(
            vertices, mesh.positions,
            "exactly: the shortest decimals read back"
        );
        let triangles: Vec<[u32; 3]> = model
            .descendants()
            .filter(|n| n.has_tag_name("triangle"))
            .map(|n| ["v1", "v2", "v3"].map(|a| n.attribute(a).unwrap().parse().unwrap()))
            .collect();
        assert_eq!(triangles, mesh.triangles);
        assert!(
            model
                .descendants()
                .any(|n| n.has_tag_name("item") && n.attribute("objectid") == Some("1"))
        );
    }

    /// The JSON and the binary chunk of a GLB, checked against the container's layout.
    fn chunks(bytes: &[u8]) -> (serde_json::Value, &[u8]) {
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        assert_eq!(&bytes[..4], b"glTF");
        assert_eq!(word(4), 2);
        assert_eq!(word(8), bytes.len());
        let json_len = word(12);
        assert_eq!(&bytes[16..20], b"JSON");
        assert!(json_len.is_multiple_of(4));
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
        let bin_at = 20 + json_len;
        assert_eq!(&bytes[bin_at + 4..bin_at + 8], b"BIN\0");
        let bin = &bytes[bin_at + 8..bin_at + 8 + word(bin_at)];
        assert_eq!(bin_at + 8 + bin.len(), bytes.len());
        (json, bin)
    }

    /// A GLB read back: positions in metres with +Y up, unit normals turned alike, the indices the
    /// triangles', the bounds and the generator set; a degenerate triangle left out.
    #[test]
    fn a_glb_reads_back_as_the_mesh_in_metres_y_up() {
        let mut mesh = test_mesh();
        let kept = mesh.triangles.len();
        mesh.triangles.push([0, 0, 1]);
        let bytes = ExportFormat::Glb.write(&mesh, "fish").unwrap();
        let (json, bin) = chunks(&bytes);
        assert!(
            json["asset"]["generator"]
                .as_str()
                .unwrap()
                .starts_with("bezsolid")
        );
        assert_eq!(json["asset"]["version"], "2.0");
        assert_eq!(json["meshes"][0]["name"], "fish");
        let accessor = |k: usize| &json["accessors"][k];
        let view_of = |k: usize| {
            let v = &json["bufferViews"][accessor(k)["bufferView"].as_u64().unwrap() as usize];
            let at = v["byteOffset"].as_u64().unwrap() as usize;
            &bin[at..at + v["byteLength"].as_u64().unwrap() as usize]
        };
        let attributes = &json["meshes"][0]["primitives"][0]["attributes"];
        let (p, n) = (
            attributes["POSITION"].as_u64().unwrap() as usize,
            attributes["NORMAL"].as_u64().unwrap() as usize,
        );
        let i = json["meshes"][0]["primitives"][0]["indices"]
            .as_u64()
            .unwrap() as usize;
        let floats = |bytes: &[u8]| -> Vec<f32> {
            bytes
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect()
        };
        let positions = floats(view_of(p));
        assert_eq!(accessor(p)["count"], mesh.positions.len());
        for (q, v) in positions.chunks_exact(3).zip(&mesh.positions) {
            let want = [v.x / 1e3, v.z / 1e3, -v.y / 1e3];
            for k in 0..3 {
                assert!((f64::from(q[k]) - want[k]).abs() < 1e-9, "{q:?} {v}");
            }
        }
        for k in 0..3 {
            let column = positions.iter().skip(k).step_by(3);
            let lo = column.clone().copied().fold(f32::INFINITY, f32::min);
            let hi = column.copied().fold(f32::NEG_INFINITY, f32::max);
            assert_eq!(accessor(p)["min"][k].as_f64().unwrap(), f64::from(lo));
            assert_eq!(accessor(p)["max"][k].as_f64().unwrap(), f64::from(hi));
        }
        for (q, v) in floats(view_of(n)).chunks_exact(3).zip(&mesh.normals) {
            let len = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
            assert!((len - 1.0).abs() < 1e-6);
            let want = v.normalize();
            let want = [want.x, want.z, -want.y];
            for k in 0..3 {
                assert!((f64::from(q[k]) - want[k]).abs() < 1e-6);
            }
        }
        let indices: Vec<u32> = view_of(i)
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(indices.len(), 3 * kept, "the degenerate triangle left out");
        assert_eq!(indices, mesh.triangles[..kept].concat());
    }

    #[test]
    fn formats_are_named_and_parsed() {
        for f in ExportFormat::ALL {
            assert_eq!(f.extension().parse::<ExportFormat>(), Ok(f));
            assert_eq!(
                ExportFormat::of_path(&alloc::format!("a.B.{}", f.extension().to_uppercase())),
                Some(f)
            );
        }
        assert_eq!(ExportFormat::of_path("x.step"), None);
        assert!(
            "gltf"
                .parse::<ExportFormat>()
                .unwrap_err()
                .to_string()
                .contains("3mf and glb")
        );
        let mesh = Mesh {
            positions: vec![DVec3::new(f64::NAN, 0.0, 0.0)],
            normals: vec![DVec3::Z],
            triangles: vec![],
        };
        assert!(ExportFormat::ThreeMf.write(&mesh, "").is_err());
        assert!(ExportFormat::Glb.write(&mesh, "").is_err());
        assert_eq!(
            serde_json::to_string(&ExportFormat::ThreeMf).unwrap(),
            "\"3mf\""
        );
        assert_eq!(
            serde_json::from_str::<ExportFormat>("\"glb\"").unwrap(),
            ExportFormat::Glb
        );
    }
}

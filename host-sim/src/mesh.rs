//! Triangle meshes from files: OBJ (via `tobj`) and PLY (via `ply-rs-bw`), validated into a
//! [`TriMesh`], and packed into texcore's device format ([`texcore::packed_mesh`]).
//!
//! Guarantees:
//! - every accepted mesh has between 1 and [`MAX_TRIANGLES`] triangles over at most
//!   [`MAX_VERTICES`] vertices, every index in range, every coordinate finite with magnitude at
//!   most [`MAX_COORD`], no degenerate triangle (two equal corners or zero area) and no
//!   duplicate triangle (the same three corner positions in any order);
//! - every rejection is a [`MeshError`] naming the file and, where the problem has one, the line
//!   (or for binary PLY the element) it is on; files larger than [`MAX_FILE_BYTES`] are refused
//!   before they are read; nothing panics on any input.

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// Most triangles a mesh may have (the device format indexes them with `u16`).
pub const MAX_TRIANGLES: usize = texcore::packed_mesh::MAX_TRIANGLES;
/// Most vertices a mesh may have (`u16` indices).
pub const MAX_VERTICES: usize = texcore::packed_mesh::MAX_VERTICES;
/// Largest coordinate magnitude accepted (the device stores `Q16.16`).
pub const MAX_COORD: f64 = 16384.0;
/// Largest mesh file read.
pub const MAX_FILE_BYTES: u64 = 32 << 20;

/// Where in a file a problem is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// The whole file.
    File,
    /// A 1-based line.
    Line(usize),
    /// A 0-based element of a binary PLY section (`vertex` or `face`).
    Element(&'static str, usize),
}

/// A mesh rejected, with the file and place.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshError {
    /// The file as named by the caller.
    pub file: String,
    /// Where in it.
    pub at: Location,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            Location::File => write!(f, "{}: {}", self.file, self.message),
            Location::Line(l) => write!(f, "{}:{}: {}", self.file, l, self.message),
            Location::Element(s, i) => write!(f, "{}: {} {}: {}", self.file, s, i, self.message),
        }
    }
}

impl std::error::Error for MeshError {}

/// A validated triangle mesh (see the module guarantees).
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Validates positions and triangles; `where_vertex(i)` and `where_triangle(t)` say where
    /// vertex `i` and triangle `t` came from, for the error.
    pub fn new(
        file: &str,
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        where_vertex: &dyn Fn(usize) -> Location,
        where_triangle: &dyn Fn(usize) -> Location,
    ) -> Result<TriMesh, MeshError> {
        let err = |at, message: String| MeshError {
            file: file.to_string(),
            at,
            message,
        };
        if triangles.is_empty() {
            return Err(err(Location::File, "no triangles (empty mesh)".into()));
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(err(
                Location::File,
                format!(
                    "{} triangles: more than the capacity of {MAX_TRIANGLES}",
                    triangles.len()
                ),
            ));
        }
        if positions.len() > MAX_VERTICES {
            return Err(err(
                Location::File,
                format!(
                    "{} vertices: more than the capacity of {MAX_VERTICES}",
                    positions.len()
                ),
            ));
        }
        for (i, p) in positions.iter().enumerate() {
            if p.iter().any(|c| !c.is_finite()) {
                return Err(err(
                    where_vertex(i),
                    format!("vertex {} is not finite", i + 1),
                ));
            }
            if p.iter().any(|c| c.abs() > MAX_COORD) {
                return Err(err(
                    where_vertex(i),
                    format!("vertex {} has a coordinate beyond +-{MAX_COORD}", i + 1),
                ));
            }
        }
        let mut seen: HashMap<[[u64; 3]; 3], usize> = HashMap::new();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(err(
                    where_triangle(t),
                    format!(
                        "vertex index {} out of range (the mesh has {} vertices)",
                        bad as u64 + 1,
                        positions.len()
                    ),
                ));
            }
            let [a, b, c] = tri.map(|i| positions[i as usize]);
            if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
                return Err(err(
                    where_triangle(t),
                    "degenerate triangle (repeated vertex)".into(),
                ));
            }
            if triangle_area(a, b, c) <= 1e-12 * longest_edge(a, b, c).powi(2) {
                return Err(err(
                    where_triangle(t),
                    "degenerate triangle (zero area)".into(),
                ));
            }
            let mut key = [a, b, c].map(|p| p.map(f64::to_bits));
            key.sort_unstable();
            if let Some(first) = seen.insert(key, t) {
                let first = match where_triangle(first) {
                    Location::Line(l) => format!("line {l}"),
                    Location::Element(s, i) => format!("{s} {i}"),
                    Location::File => format!("triangle {}", first + 1),
                };
                return Err(err(
                    where_triangle(t),
                    format!("duplicate triangle (same corners as {first})"),
                ));
            }
        }
        Ok(TriMesh {
            positions,
            triangles,
        })
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// Triangles (counter-clockwise seen from outside for well-formed files).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [[f64; 3]; 3] {
        self.triangles[t].map(|i| self.positions[i as usize])
    }

    /// Axis-aligned bounds `[min, max]`.
    pub fn bounds(&self) -> [[f64; 3]; 2] {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        [lo, hi]
    }

    /// A mesh built in code (the test meshes); same validation as the loaders.
    pub fn from_parts(
        name: &str,
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
    ) -> Result<TriMesh, MeshError> {
        TriMesh::new(name, positions, triangles, &|_| Location::File, &|_| {
            Location::File
        })
    }

    /// The mesh in texcore's device format ([`texcore::packed_mesh`]): positions rounded to
    /// `Q16.16`. Fails (naming `file`) if rounding makes a triangle degenerate.
    pub fn pack(&self, file: &str) -> Result<Vec<u8>, MeshError> {
        let q = |c: f64| (c * 65536.0).round() as i32;
        let positions: Vec<[i32; 3]> = self.positions.iter().map(|p| p.map(q)).collect();
        let triangles: Vec<[u16; 3]> = self.triangles.iter().map(|t| t.map(|i| i as u16)).collect();
        let bytes = encode_packed(&positions, &triangles);
        match texcore::packed_mesh::PackedMesh::new(&bytes) {
            Ok(_) => Ok(bytes),
            Err(e) => Err(MeshError {
                file: file.to_string(),
                at: Location::File,
                message: format!("cannot be packed: {e}"),
            }),
        }
    }
}

/// The device format's bytes for `positions` (`Q16.16`) and `triangles` (see
/// [`texcore::packed_mesh`] for the layout). Not validated: [`TriMesh::pack`] checks them.
pub fn encode_packed(positions: &[[i32; 3]], triangles: &[[u16; 3]]) -> Vec<u8> {
    use texcore::packed_mesh::{checksum, MAGIC};
    let mut out = Vec::with_capacity(12 + 12 * positions.len() + 6 * triangles.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&(positions.len() as u16).to_le_bytes());
    out.extend_from_slice(&(triangles.len() as u16).to_le_bytes());
    for p in positions {
        for c in p {
            out.extend_from_slice(&c.to_le_bytes());
        }
    }
    for t in triangles {
        for i in t {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    let h = checksum(&out);
    out.extend_from_slice(&h.to_le_bytes());
    out
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Area of a triangle in space.
pub fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

/// Length of a triangle's longest edge.
pub fn longest_edge(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    norm(sub(b, a)).max(norm(sub(c, b))).max(norm(sub(a, c)))
}

/// Reads a mesh file by extension (`.obj` or `.ply`), at most [`MAX_FILE_BYTES`].
pub fn load(path: &Path) -> Result<TriMesh, MeshError> {
    let name = path.display().to_string();
    let err = |message: String| MeshError {
        file: name.clone(),
        at: Location::File,
        message,
    };
    let len = std::fs::metadata(path)
        .map_err(|e| err(format!("cannot read: {e}")))?
        .len();
    if len > MAX_FILE_BYTES {
        return Err(err(format!(
            "{len} bytes: larger than the limit of {MAX_FILE_BYTES}"
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| err(format!("cannot read: {e}")))?;
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ext.as_str() {
        "obj" => load_obj(&name, &bytes),
        "ply" => load_ply(&name, &bytes),
        _ => Err(err("unknown mesh format (expected .obj or .ply)".into())),
    }
}

/// Parses an OBJ file's bytes (`name` is used in errors). Polygons are fan-triangulated;
/// normals, texture coordinates, groups and materials are ignored.
pub fn load_obj(name: &str, bytes: &[u8]) -> Result<TriMesh, MeshError> {
    let err = |at, message: String| MeshError {
        file: name.to_string(),
        at,
        message,
    };
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(err(Location::File, "file larger than the limit".into()));
    }
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        err(Location::Line(line), "not UTF-8 text".into())
    })?;
    // A first pass finds the line of every vertex and face and checks their syntax, so that
    // every later problem can name its line, and writes the text tobj parses: vertex positions
    // and faces of absolute position indices only. tobj never sees an index this pass has not
    // checked (its own resolution of relative texture-coordinate indices overflows on some).
    let mut vertex_lines = Vec::new();
    let (mut texcoords, mut normals) = (0i64, 0i64);
    let mut clean = String::with_capacity(text.len());
    let mut face_lines: Vec<usize> = Vec::new(); // one entry per triangle
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let mut words = raw.split('#').next().unwrap_or("").split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 {
                    return Err(err(
                        Location::Line(line),
                        "a vertex needs three coordinates".into(),
                    ));
                }
                for c in &coords[..3] {
                    let v: f64 = c.parse().map_err(|_| {
                        err(
                            Location::Line(line),
                            format!("bad vertex coordinate \"{}\"", c.escape_debug()),
                        )
                    })?;
                    if !v.is_finite() {
                        return Err(err(Location::Line(line), "vertex is not finite".into()));
                    }
                    if v.abs() > MAX_COORD {
                        return Err(err(
                            Location::Line(line),
                            format!("vertex coordinate {c} beyond +-{MAX_COORD}"),
                        ));
                    }
                }
                clean.push_str("v ");
                clean.push_str(&coords[..3].join(" "));
                clean.push('\n');
                vertex_lines.push(line);
                if vertex_lines.len() > MAX_VERTICES {
                    return Err(err(
                        Location::Line(line),
                        format!("more than the capacity of {MAX_VERTICES} vertices"),
                    ));
                }
            }
            Some("f") => {
                let corners: Vec<&str> = words.collect();
                if corners.len() < 3 {
                    return Err(err(
                        Location::Line(line),
                        "a face needs three corners".into(),
                    ));
                }
                clean.push('f');
                for c in &corners {
                    let mut parts = c.split('/');
                    let first = parts.next().unwrap_or("");
                    let resolved =
                        obj_index(first, vertex_lines.len() as i64, "vertex").map_err(|m| {
                            err(
                                Location::Line(line),
                                format!("{m} in \"{}\"", c.escape_debug()),
                            )
                        })?;
                    // Texture coordinate and normal (ignored, but checked): empty or in range.
                    for (part, count, what) in [
                        (parts.next(), texcoords, "texture coordinate"),
                        (parts.next(), normals, "normal"),
                    ] {
                        if let Some(p) = part.filter(|p| !p.is_empty()) {
                            obj_index(p, count, what).map_err(|m| {
                                err(
                                    Location::Line(line),
                                    format!("{m} in \"{}\"", c.escape_debug()),
                                )
                            })?;
                        }
                    }
                    if parts.next().is_some() {
                        return Err(err(
                            Location::Line(line),
                            format!(
                                "bad face corner \"{}\" (more than v/vt/vn)",
                                c.escape_debug()
                            ),
                        ));
                    }
                    clean.push(' ');
                    clean.push_str(&resolved.to_string());
                }
                clean.push('\n');
                for _ in 2..corners.len() {
                    face_lines.push(line);
                }
                if face_lines.len() > MAX_TRIANGLES {
                    return Err(err(
                        Location::Line(line),
                        format!("more than the capacity of {MAX_TRIANGLES} triangles"),
                    ));
                }
            }
            Some("vt") => texcoords += 1,
            Some("vn") => normals += 1,
            _ => {}
        }
    }
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut std::io::Cursor::new(clean), &opts, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| err(Location::File, format!("malformed OBJ: {e}")))?;
    // tobj gives each group its own vertices; merge them back by position so that shared
    // vertices are shared again.
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut index: HashMap<[u64; 3], u32> = HashMap::new();
    let mut triangles = Vec::new();
    for m in &models {
        let p = &m.mesh.positions;
        let mut local = Vec::with_capacity(p.len() / 3);
        for c in p.chunks_exact(3) {
            let v = [c[0] as f64, c[1] as f64, c[2] as f64];
            let next = positions.len() as u32;
            let id = *index.entry(v.map(f64::to_bits)).or_insert_with(|| {
                positions.push(v);
                next
            });
            local.push(id);
        }
        for t in m.mesh.indices.chunks_exact(3) {
            let get = |i: u32| local.get(i as usize).copied().unwrap_or(u32::MAX);
            triangles.push([get(t[0]), get(t[1]), get(t[2])]);
        }
    }
    // Vertex problems were reported with their lines by the first pass.
    TriMesh::new(name, positions, triangles, &|_| Location::File, &|t| {
        face_lines
            .get(t)
            .map_or(Location::File, |&l| Location::Line(l))
    })
}

/// Resolves an OBJ index (`1..=count`, or `-1` for the last so far) against `count` items of
/// its kind read so far; `Err` says why not.
fn obj_index(word: &str, count: i64, what: &str) -> Result<i64, String> {
    let i: i64 = word
        .parse()
        .map_err(|_| format!("bad {what} index \"{}\"", word.escape_debug()))?;
    let resolved = if i < 0 {
        count.saturating_add(i).saturating_add(1)
    } else {
        i
    };
    if i == 0 || resolved < 1 || resolved > count {
        return Err(format!(
            "{what} index {i} out of range ({count} {what}s so far)"
        ));
    }
    Ok(resolved)
}

/// Parses a PLY file's bytes (ASCII or binary; `vertex` with `x`, `y`, `z` and `face` with
/// `vertex_indices` or `vertex_index`). Polygons are fan-triangulated.
pub fn load_ply(name: &str, bytes: &[u8]) -> Result<TriMesh, MeshError> {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::{DefaultElement, Encoding, Property};
    let err = |at, message: String| MeshError {
        file: name.to_string(),
        at,
        message,
    };
    if bytes.is_empty() {
        return Err(err(Location::File, "empty file".into()));
    }
    let parser = Parser::<DefaultElement>::new();
    let malformed = |e: std::io::Error| {
        let msg = e.to_string();
        // ply-rs reports "Line N: ..." for text problems.
        let line = msg
            .strip_prefix("Line ")
            .and_then(|r| r.split(':').next())
            .and_then(|n| n.trim().parse().ok());
        let first = msg.lines().next().unwrap_or("").to_string();
        match line {
            Some(l) => err(Location::Line(l), format!("malformed PLY: {first}")),
            None => err(Location::File, format!("malformed PLY: {first}")),
        }
    };
    // The header's element counts are checked before any payload is read: the parser reads
    // `count` entries of an element whatever the file holds, and an element without properties
    // reads no bytes, so only these bounds keep its memory bounded.
    let header = parser
        .read_ply_header(&mut std::io::Cursor::new(bytes))
        .map_err(malformed)?;
    check_ply_counts(&header, bytes.len()).map_err(|m| err(Location::File, m))?;
    let ply = parser
        .read_ply(&mut std::io::Cursor::new(bytes))
        .map_err(malformed)?;
    let ascii = ply.header.encoding == Encoding::Ascii;
    // Lines of the header (the payload starts after `end_header`).
    let header_lines = bytes
        .split(|&b| b == b'\n')
        .position(|l| l.starts_with(b"end_header"))
        .map_or(0, |p| p + 1);
    let vertex_count = ply.payload.get("vertex").map_or(0, |v| v.len());
    let where_vertex = |i: usize| {
        if ascii {
            Location::Line(header_lines + i + 1)
        } else {
            Location::Element("vertex", i)
        }
    };
    let where_face = |i: usize| {
        if ascii {
            Location::Line(header_lines + vertex_count + i + 1)
        } else {
            Location::Element("face", i)
        }
    };
    let scalar = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(v) => *v as f64,
            Property::Double(v) => *v,
            Property::Char(v) => *v as f64,
            Property::UChar(v) => *v as f64,
            Property::Short(v) => *v as f64,
            Property::UShort(v) => *v as f64,
            Property::Int(v) => *v as f64,
            Property::UInt(v) => *v as f64,
            _ => return None,
        })
    };
    let mut positions = Vec::with_capacity(vertex_count.min(MAX_VERTICES + 1));
    if let Some(vs) = ply.payload.get("vertex") {
        if vs.len() > MAX_VERTICES {
            return Err(err(
                Location::File,
                format!(
                    "{} vertices: more than the capacity of {MAX_VERTICES}",
                    vs.len()
                ),
            ));
        }
        for (i, v) in vs.iter().enumerate() {
            let get = |k: &str| scalar(v.get(k));
            match (get("x"), get("y"), get("z")) {
                (Some(x), Some(y), Some(z)) => positions.push([x, y, z]),
                _ => {
                    return Err(err(
                        where_vertex(i),
                        "vertex without numeric x, y, z".into(),
                    ))
                }
            }
        }
    }
    let mut triangles = Vec::new();
    let mut tri_face = Vec::new();
    if let Some(fs) = ply.payload.get("face") {
        for (f, face) in fs.iter().enumerate() {
            let list = face
                .get("vertex_indices")
                .or_else(|| face.get("vertex_index"));
            let idx: Vec<i64> = match list {
                Some(Property::ListChar(l)) => l.iter().map(|&i| i as i64).collect(),
                Some(Property::ListUChar(l)) => l.iter().map(|&i| i as i64).collect(),
                Some(Property::ListShort(l)) => l.iter().map(|&i| i as i64).collect(),
                Some(Property::ListUShort(l)) => l.iter().map(|&i| i as i64).collect(),
                Some(Property::ListInt(l)) => l.iter().map(|&i| i as i64).collect(),
                Some(Property::ListUInt(l)) => l.iter().map(|&i| i as i64).collect(),
                _ => {
                    return Err(err(
                        where_face(f),
                        "face without an integer vertex_indices list".into(),
                    ))
                }
            };
            if idx.len() < 3 {
                return Err(err(where_face(f), "a face needs three corners".into()));
            }
            if let Some(&bad) = idx
                .iter()
                .find(|&&i| i < 0 || i as usize >= positions.len())
            {
                return Err(err(
                    where_face(f),
                    format!(
                        "vertex index {bad} out of range (the mesh has {} vertices)",
                        positions.len()
                    ),
                ));
            }
            for k in 2..idx.len() {
                triangles.push([idx[0] as u32, idx[k - 1] as u32, idx[k] as u32]);
                tri_face.push(f);
            }
            if triangles.len() > MAX_TRIANGLES {
                return Err(err(
                    where_face(f),
                    format!("more than the capacity of {MAX_TRIANGLES} triangles"),
                ));
            }
        }
    }
    TriMesh::new(name, positions, triangles, &where_vertex, &|t| {
        where_face(tri_face.get(t).copied().unwrap_or(0))
    })
}

/// The most entries all of a PLY file's elements may declare together: a mesh at capacity
/// plus as many entries again for elements texcore ignores (edges, materials).
pub const MAX_PLY_ENTRIES: usize = 2 * (MAX_VERTICES + MAX_TRIANGLES);

/// Checks a PLY header's element counts against the capacities and, for a binary file, against
/// the bytes a payload of that many entries needs at least; `Err` says which element is too big.
fn check_ply_counts(header: &ply_rs_bw::ply::Header, file_bytes: usize) -> Result<(), String> {
    use ply_rs_bw::ply::{Encoding, PropertyType, ScalarType};
    let size = |t: &ScalarType| match t {
        ScalarType::Char | ScalarType::UChar => 1u64,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    };
    let binary = header.encoding != Encoding::Ascii;
    let mut total = 0usize;
    let mut least_bytes = 0u64;
    for (name, e) in &header.elements {
        let cap = match name.as_str() {
            "vertex" => MAX_VERTICES,
            "face" => MAX_TRIANGLES,
            _ => MAX_PLY_ENTRIES,
        };
        if e.count > cap {
            return Err(format!(
                "element \"{}\" declares {} entries: more than the capacity of {cap}",
                name.escape_debug(),
                e.count
            ));
        }
        total = total.saturating_add(e.count);
        if total > MAX_PLY_ENTRIES {
            return Err(format!(
                "the elements declare more than {MAX_PLY_ENTRIES} entries together"
            ));
        }
        // Every entry of a binary element takes at least its scalars and its lists' lengths.
        let per_entry: u64 = e
            .properties
            .values()
            .map(|p| match &p.data_type {
                PropertyType::Scalar(t) | PropertyType::List(t, _) => size(t),
            })
            .sum();
        least_bytes = least_bytes.saturating_add(per_entry.saturating_mul(e.count as u64));
    }
    if binary && least_bytes > file_bytes as u64 {
        return Err(format!(
            "the header declares at least {least_bytes} bytes of binary data; the file has {file_bytes}"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(text: &str) -> Result<TriMesh, MeshError> {
        load_obj("t.obj", text.as_bytes())
    }

    const TET: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

    #[test]
    fn good_obj_loads() {
        let m = obj(TET).unwrap();
        assert_eq!(m.triangles().len(), 4);
        assert_eq!(m.positions().len(), 4);
        // A quad fan-triangulated, comments and normals ignored.
        let m = obj("# c\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n")
            .unwrap();
        assert_eq!(m.triangles().len(), 2);
        // Texture coordinates and relative indices in range.
        let m =
            obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -3/1/1 -2/-1/1 -1/1/-1\n").unwrap();
        assert_eq!(m.triangles().len(), 1);
    }

    #[test]
    fn bad_obj_names_the_line() {
        let cases: &[(&str, usize, &str)] = &[
            ("v 0 0 0\nv 1 0 x\n", 2, "bad vertex"),
            ("v 0 0 0\nv 1 0 NaN\n", 2, "not finite"),
            ("v 0 0 0\nv 1e9 0 0\n", 2, "beyond"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "out of range"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n", 4, "degenerate"),
            ("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", 4, "zero area"),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\nf 2 3 1\n",
                6,
                "duplicate",
            ),
            ("v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "three corners"),
            // Found by the `mesh` fuzz target: a relative texture-coordinate index past the
            // start overflowed tobj's own resolution (a panic); every index is checked first.
            (
                "v 0 0 4\nvt  1 0\nv 0 1 0\nf 1/-211 2/0 1\n",
                4,
                "texture coordinate index -211 out of range",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
                4,
                "texture coordinate index 1",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//1 3//1\n",
                4,
                "normal index 2",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n",
                4,
                "bad texture coordinate",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1/1 2 3\n",
                6,
                "more than v/vt/vn",
            ),
            (
                "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n",
                4,
                "vertex index -4",
            ),
        ];
        for (text, line, what) in cases {
            let e = obj(text).unwrap_err();
            assert_eq!(e.at, Location::Line(*line), "{text:?}: {e}");
            assert!(e.to_string().contains(what), "{text:?}: {e}");
            assert!(e.to_string().starts_with(&format!("t.obj:{line}:")), "{e}");
        }
        let e = obj("").unwrap_err();
        assert!(e.to_string().contains("no triangles"), "{e}");
        let e = obj("v 0 0 0\n").unwrap_err();
        assert!(e.to_string().contains("no triangles"), "{e}");
    }

    #[test]
    fn capacity_is_checked() {
        let mut s = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
        for _ in 0..=MAX_TRIANGLES {
            s.push_str("f 1 2 3\n");
        }
        let e = obj(&s).unwrap_err();
        assert!(e.to_string().contains("capacity"), "{e}");
    }

    #[test]
    fn ply_ascii_and_errors() {
        let head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let good = format!("{head}0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
        let m = load_ply("t.ply", good.as_bytes()).unwrap();
        assert_eq!(m.triangles(), &[[0, 1, 2]]);
        let bad = format!("{head}0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
        let e = load_ply("t.ply", bad.as_bytes()).unwrap_err();
        assert_eq!(e.at, Location::Line(13), "{e}");
        let bad = format!("{head}0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n");
        let e = load_ply("t.ply", bad.as_bytes()).unwrap_err();
        assert_eq!(e.at, Location::Line(11), "{e}");
        let e = load_ply("t.ply", b"plx\n").unwrap_err();
        assert!(e.to_string().starts_with("t.ply"), "{e}");
        assert!(load_ply("t.ply", b"").is_err());
    }

    #[test]
    fn ply_counts_are_bounded_before_the_payload() {
        let bin = "ply\nformat binary_little_endian 1.0\n";
        let xyz = "property float x\nproperty float y\nproperty float z\n";
        let face = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
        let cases: [(String, &str); 4] = [
            // Far more vertices than the capacity.
            (
                format!("{bin}element vertex 488888888887\n{xyz}{face}"),
                "capacity",
            ),
            // An element without properties reads no bytes: only its count bounds it.
            (
                format!("{bin}element junk 4000000000\nelement vertex 3\n{xyz}{face}"),
                "capacity",
            ),
            (
                format!("{bin}element a 200000\nelement b 200000\nelement vertex 3\n{xyz}{face}"),
                "together",
            ),
            // Within the capacity, but more entries than the file has bytes for.
            (
                format!("{bin}element vertex 60000\n{xyz}{face}"),
                "binary data",
            ),
        ];
        for (text, want) in cases {
            let e = load_ply("t.ply", text.as_bytes()).unwrap_err();
            assert!(e.to_string().contains(want), "{e}");
            assert_eq!(e.file, "t.ply");
        }
        // The fuzzer's find: a vertex element redefined, 488888888887 entries without bytes.
        let e = load_ply(
            "t.ply",
            include_bytes!("../../fuzz/corpus/mesh/ply-redefined-element")[1..].as_ref(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("capacity"), "{e}");
    }

    #[test]
    fn bunny_loads_and_packs() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/meshes/bunny.obj");
        let m = load(&path).unwrap();
        assert_eq!(m.triangles().len(), 3674);
        let bytes = m.pack("bunny.obj").unwrap();
        let p = texcore::packed_mesh::PackedMesh::new(&bytes).unwrap();
        assert_eq!(p.triangle_count(), 3674);
    }
}

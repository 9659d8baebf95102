//! Mesh loaders and the device mesh format: the first byte picks the input's kind, the rest is
//! the file.
//!
//! - OBJ (`host_sim::mesh::load_obj`) and PLY, ASCII or binary (`load_ply`): every input is a
//!   mesh or a `MeshError` naming the file (never a panic); an accepted mesh keeps the module's
//!   guarantees (1 to `MAX_TRIANGLES` triangles, indices in range, finite coordinates within
//!   `MAX_COORD`, no degenerate triangle), and packing it gives bytes that
//!   `texcore::packed_mesh::PackedMesh` accepts with the same counts, or an error naming the file.
//! - The packed format itself (`PackedMesh::new`), as given and with its magic and checksum made
//!   right (so the structural checks behind them are reached): accepted bytes give in-range
//!   indices and triangles that can all be read.
#![no_main]

use host_sim::mesh::{self, TriMesh, MAX_COORD, MAX_TRIANGLES};
use libfuzzer_sys::fuzz_target;
use texcore::packed_mesh::{checksum, PackedMesh, MAGIC};

fn check_mesh(m: &TriMesh, name: &str) {
    let n = m.triangles().len();
    assert!((1..=MAX_TRIANGLES).contains(&n), "{n} triangles accepted");
    for p in m.positions() {
        assert!(
            p.iter().all(|c| c.is_finite() && c.abs() <= MAX_COORD),
            "{p:?}"
        );
    }
    for (t, tri) in m.triangles().iter().enumerate() {
        assert!(tri.iter().all(|&i| (i as usize) < m.positions().len()));
        let [a, b, c] = m.corners(t);
        assert!(
            mesh::triangle_area(a, b, c) > 0.0,
            "degenerate triangle {t} accepted"
        );
    }
    match m.pack(name) {
        Ok(bytes) => {
            let p = PackedMesh::new(&bytes).expect("packed bytes are accepted");
            assert_eq!(p.triangle_count() as usize, n);
            assert_eq!(p.vertex_count() as usize, m.positions().len());
        }
        Err(e) => assert_eq!(e.file, name),
    }
}

fn check_packed(bytes: &[u8]) {
    if let Ok(p) = PackedMesh::new(bytes) {
        let v = p.vertex_count();
        assert!(p.triangle_count() >= 1 && v >= 3);
        for t in 0..p.triangle_count() {
            assert!(p.indices(t).iter().all(|&i| i < v));
        }
        assert_eq!(p.triangles().count(), p.triangle_count() as usize);
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&kind, file)) = data.split_first() else {
        return;
    };
    match kind % 4 {
        0 => match mesh::load_obj("fuzz.obj", file) {
            Ok(m) => check_mesh(&m, "fuzz.obj"),
            Err(e) => assert_eq!(e.file, "fuzz.obj"),
        },
        1 => match mesh::load_ply("fuzz.ply", file) {
            Ok(m) => check_mesh(&m, "fuzz.ply"),
            Err(e) => assert_eq!(e.file, "fuzz.ply"),
        },
        2 => check_packed(file),
        _ => {
            // Magic and checksum made right: the checks behind them get the input.
            if file.len() < 12 {
                return;
            }
            let mut b = file.to_vec();
            b[..4].copy_from_slice(&MAGIC);
            let body = b.len() - 4;
            let h = checksum(&b[..body]);
            b[body..].copy_from_slice(&h.to_le_bytes());
            check_packed(&b);
        }
    }
});

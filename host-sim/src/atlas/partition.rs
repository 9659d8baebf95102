//! Balanced hierarchical partition of a mesh's faces for the MIP-mappable atlas (Carr & Hart
//! 2002, section 4.3): a quadtree whose every node splits its faces into four sections of
//! (nearly) equal size, each grown as one contiguous region of the dual graph where the mesh
//! allows, by recursive bisection.
//!
//! Each bisection grows the first part breadth-first over the dual graph (faces sharing an edge)
//! from a peripheral face of the node (the last face a breadth-first search from any face
//! reaches), until it holds its share; the rest is the second part. The result is the order of
//! the faces along the quadtree's leaves (pairs of faces), which the layout places in Z order,
//! so every quadtree node is one square of the atlas.
//!
//! Guarantees: the order is a permutation of the faces; section sizes differ by at most one
//! pair per level. Contiguity is measured ([`Partition::components`]), not promised: a part
//! may fall into several components when the growth runs into the mesh's border or a
//! previously taken region.

use std::collections::{HashMap, VecDeque};

/// Faces sharing an edge, per face.
pub fn dual_graph(triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut edges: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (f, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges
                .entry((a.min(b), a.max(b)))
                .or_default()
                .push(f as u32);
        }
    }
    let mut adj = vec![Vec::new(); triangles.len()];
    for faces in edges.values() {
        for &a in faces {
            for &b in faces {
                if a != b && !adj[a as usize].contains(&b) {
                    adj[a as usize].push(b);
                }
            }
        }
    }
    adj
}

/// A face order for a quadtree of `4^levels` leaves of two faces each.
#[derive(Clone, Debug)]
pub struct Partition {
    /// Faces in leaf order: leaf `k` holds entries `2k` and `2k + 1` (`u32::MAX`: empty).
    pub order: Vec<u32>,
    /// Levels of the quadtree (`4^levels >= ` pairs).
    pub levels: u32,
}

impl Partition {
    /// Partitions the faces of `triangles`.
    pub fn new(triangles: &[[u32; 3]]) -> Partition {
        let adj = dual_graph(triangles);
        let pairs = triangles.len().div_ceil(2);
        let mut levels = 0u32;
        while 4usize.pow(levels) < pairs {
            levels += 1;
        }
        let all: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut order = Vec::with_capacity(triangles.len());
        let mut member = vec![false; triangles.len()];
        split(&adj, &all, 4usize.pow(levels), &mut member, &mut order);
        Partition { order, levels }
    }

    /// For every quadtree level from the root's children down (`1..=levels`), the mean number
    /// of connected components (in the dual graph) of the non-empty sections of that level:
    /// 1.0 means every section is contiguous.
    pub fn components(&self, triangles: &[[u32; 3]]) -> Vec<f64> {
        let adj = dual_graph(triangles);
        let mut out = Vec::new();
        for level in 1..=self.levels {
            let leaves_per = 4usize.pow(self.levels - level);
            let faces_per = 2 * leaves_per;
            let mut total = 0usize;
            let mut sections = 0usize;
            for chunk in self.order.chunks(faces_per) {
                let faces: Vec<u32> = chunk.iter().copied().filter(|&f| f != u32::MAX).collect();
                if !faces.is_empty() {
                    total += count_components(&adj, &faces);
                    sections += 1;
                }
            }
            out.push(total as f64 / sections.max(1) as f64);
        }
        out
    }
}

fn count_components(adj: &[Vec<u32>], faces: &[u32]) -> usize {
    let set: std::collections::HashSet<u32> = faces.iter().copied().collect();
    let mut seen = std::collections::HashSet::new();
    let mut n = 0;
    for &f in faces {
        if !seen.insert(f) {
            continue;
        }
        n += 1;
        let mut q = VecDeque::from([f]);
        while let Some(x) = q.pop_front() {
            for &y in &adj[x as usize] {
                if set.contains(&y) && seen.insert(y) {
                    q.push_back(y);
                }
            }
        }
    }
    n
}

/// Splits `faces` (at most `2 leaves` of them) over `leaves` leaves in Z order.
fn split(adj: &[Vec<u32>], faces: &[u32], leaves: usize, member: &mut [bool], out: &mut Vec<u32>) {
    if leaves <= 1 || faces.len() <= 2 {
        // A leaf holds one pair (two faces the growth keeps together, mostly sharing an edge);
        // empty places and leaves are `u32::MAX`.
        out.extend(
            faces
                .iter()
                .copied()
                .chain(std::iter::repeat(u32::MAX))
                .take(2),
        );
        for _ in 1..leaves {
            out.extend([u32::MAX, u32::MAX]);
        }
        return;
    }
    let quarter = leaves / 4;
    let pairs = faces.len().div_ceil(2);
    // Pairs per child as equal as possible, then in faces (the last child takes an odd face).
    let mut sizes = [0usize; 4];
    for (k, s) in sizes.iter_mut().enumerate() {
        *s = (pairs / 4 + usize::from(k < pairs % 4)).min(quarter) * 2;
    }
    let (first_half, second_half) =
        bisect(adj, faces, (sizes[0] + sizes[1]).min(faces.len()), member);
    let (a, b) = bisect(adj, &first_half, sizes[0].min(first_half.len()), member);
    let (c, d) = bisect(adj, &second_half, sizes[2].min(second_half.len()), member);
    for part in [a, b, c, d] {
        split(adj, &part, quarter, member, out);
    }
}

/// Splits `faces` into a part of `n` faces grown breadth-first from a peripheral face, and the
/// rest.
fn bisect(adj: &[Vec<u32>], faces: &[u32], n: usize, member: &mut [bool]) -> (Vec<u32>, Vec<u32>) {
    for &f in faces {
        member[f as usize] = true;
    }
    let bfs_last = |start: u32, member: &[bool]| -> u32 {
        let mut seen = std::collections::HashSet::from([start]);
        let mut q = VecDeque::from([start]);
        let mut last = start;
        while let Some(x) = q.pop_front() {
            last = x;
            for &y in &adj[x as usize] {
                if member[y as usize] && seen.insert(y) {
                    q.push_back(y);
                }
            }
        }
        last
    };
    let mut taken = Vec::with_capacity(n);
    let mut in_taken = std::collections::HashSet::new();
    let mut rest_iter = faces.iter();
    while taken.len() < n {
        // A seed: a peripheral face among those not yet taken.
        let Some(&start) = rest_iter.find(|f| !in_taken.contains(*f)) else {
            break;
        };
        let seed = bfs_last(start, member);
        let mut q = VecDeque::from([seed]);
        in_taken.insert(seed);
        member[seed as usize] = false;
        while let Some(x) = q.pop_front() {
            taken.push(x);
            if taken.len() == n {
                break;
            }
            for &y in &adj[x as usize] {
                if member[y as usize] && in_taken.insert(y) {
                    member[y as usize] = false;
                    q.push_back(y);
                }
            }
        }
        // Faces queued but not taken go back.
        for &x in &q {
            in_taken.remove(&x);
            member[x as usize] = true;
        }
    }
    let rest: Vec<u32> = faces
        .iter()
        .copied()
        .filter(|f| !in_taken.contains(f))
        .collect();
    for &f in faces {
        member[f as usize] = false;
    }
    (taken, rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip of `n` quads (2n triangles) along x.
    fn strip(n: u32) -> Vec<[u32; 3]> {
        let mut t = Vec::new();
        for i in 0..n {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
        t
    }

    #[test]
    fn order_is_a_permutation_with_balanced_contiguous_sections() {
        let t = strip(32); // 64 faces, 32 pairs: 3 levels (64 leaves)
        let p = Partition::new(&t);
        assert_eq!(p.levels, 3);
        let mut faces: Vec<u32> = p.order.iter().copied().filter(|&f| f != u32::MAX).collect();
        faces.sort_unstable();
        assert_eq!(faces, (0..64).collect::<Vec<_>>());
        assert_eq!(p.order.len(), 2 * 64);
        // A strip splits into contiguous runs at every level.
        for c in p.components(&t) {
            assert!(c <= 1.0 + 1e-9, "{c}");
        }
        // Leaf pairs share an edge.
        for pair in p.order.chunks(2) {
            if pair[0] != u32::MAX && pair[1] != u32::MAX {
                assert!(
                    dual_graph(&t)[pair[0] as usize].contains(&pair[1]),
                    "{pair:?}"
                );
            }
        }
    }
}

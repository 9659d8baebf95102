//! Balanced hierarchical partition of a mesh's faces for the MIP-mappable atlas (Carr & Hart
//! 2002, section 4.3): a quadtree whose every node splits its faces into four sections of
//! (nearly) equal size, each grown as one contiguous region of the dual graph where the mesh
//! allows, by recursive bisection.
//!
//! Each bisection grows the first part over the dual graph (faces sharing an edge) from a
//! peripheral face of the node (the last face a breadth-first search from any face reaches),
//! always taking the frontier face with the most neighbours already in the part, until it holds
//! its share; the rest is the second part. Pieces of either part cut off from its largest
//! component are then traded for as many faces along that component's border, so both parts
//! keep their sizes. The result is the order of the faces along the quadtree's leaves (pairs of
//! faces), which the layout places in Z order, so every quadtree node is one square of the
//! atlas.
//!
//! Guarantees: the order is a permutation of the faces; section sizes differ by at most one
//! pair per level. Contiguity is measured ([`Partition::components`]) and tested on a grid and
//! the bunny (every section down to 1/64 of the surface contiguous), not promised: a mesh made
//! of separate pieces (the teapot) cannot have contiguous sections, and sections of a few pairs
//! cannot always be paired along edges.

use std::collections::{HashMap, HashSet, VecDeque};

/// Faces sharing an edge, per face, in increasing order.
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
    // In face order whatever the map's order: the partition is the same on every run.
    for n in adj.iter_mut() {
        n.sort_unstable();
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
    components_of(adj, faces).len()
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

/// Splits `faces` into a part of `n` faces and the rest: the part is grown compactly from a
/// peripheral face ([`grow`]), then pieces of the rest cut off from its main component are
/// traded for as many faces of the part along that component's border ([`repair`]). Both sides
/// keep their sizes exactly.
fn bisect(adj: &[Vec<u32>], faces: &[u32], n: usize, member: &mut [bool]) -> (Vec<u32>, Vec<u32>) {
    for &f in faces {
        member[f as usize] = true;
    }
    let mut taken = grow(adj, faces, n, member);
    // The rest's stray pieces, then the region's (the same trade with the roles swapped).
    repair(adj, faces, &mut taken, member);
    let mut rest: HashSet<u32> = faces
        .iter()
        .copied()
        .filter(|f| !taken.contains(f))
        .collect();
    repair(adj, faces, &mut rest, member);
    let taken: HashSet<u32> = faces
        .iter()
        .copied()
        .filter(|f| !rest.contains(f))
        .collect();
    let (part, rest): (Vec<u32>, Vec<u32>) = faces.iter().partition(|f| taken.contains(*f));
    for &f in faces {
        member[f as usize] = false;
    }
    (part, rest)
}

/// The last face a breadth-first search from `start` over the faces `inside` accepts reaches:
/// a peripheral face of `start`'s component.
fn peripheral(adj: &[Vec<u32>], start: u32, inside: &dyn Fn(u32) -> bool) -> u32 {
    let mut seen = HashSet::from([start]);
    let mut q = VecDeque::from([start]);
    let mut last = start;
    while let Some(x) = q.pop_front() {
        last = x;
        for &y in &adj[x as usize] {
            if inside(y) && seen.insert(y) {
                q.push_back(y);
            }
        }
    }
    last
}

/// The faces next to a growing region, each with its neighbours in the region and the order it
/// was first reached: [`Frontier::pop`] takes the one with the most neighbours, the earliest
/// reached on ties (so the growth is the same on every run).
#[derive(Default)]
struct Frontier {
    faces: HashMap<u32, (u32, usize)>,
    reached: usize,
}

impl Frontier {
    /// One more neighbour of `face` is in the region.
    fn touch(&mut self, face: u32) {
        let reached = &mut self.reached;
        let e = self.faces.entry(face).or_insert_with(|| {
            *reached += 1;
            (0, *reached)
        });
        e.0 += 1;
    }

    /// Removes and returns the next face to take.
    fn pop(&mut self) -> Option<u32> {
        let (&x, _) = self
            .faces
            .iter()
            .max_by(|a, b| a.1 .0.cmp(&b.1 .0).then(b.1 .1.cmp(&a.1 .1)))?;
        self.faces.remove(&x);
        Some(x)
    }
}

/// Grows a region over the faces of the node (`member`), `n` faces, from a peripheral face: the
/// next face is always the frontier face with the most neighbours already in the region
/// (earliest reached on ties), which keeps the region round and leaves no bays that would cut
/// the rest apart. A component used up before `n` continues from a new peripheral face.
fn grow(adj: &[Vec<u32>], faces: &[u32], n: usize, member: &[bool]) -> HashSet<u32> {
    let mut taken: HashSet<u32> = HashSet::with_capacity(n);
    let mut seeds = faces.iter();
    while taken.len() < n {
        let Some(&start) = seeds.find(|f| !taken.contains(*f)) else {
            break;
        };
        let seed = peripheral(adj, start, &|y| member[y as usize] && !taken.contains(&y));
        let mut frontier = Frontier::default();
        frontier.touch(seed);
        while taken.len() < n {
            let Some(x) = frontier.pop() else {
                break;
            };
            taken.insert(x);
            for &y in &adj[x as usize] {
                if member[y as usize] && !taken.contains(&y) {
                    frontier.touch(y);
                }
            }
        }
    }
    taken
}

/// The connected components of `faces` in the dual graph, each in `faces` order.
fn components_of(adj: &[Vec<u32>], faces: &[u32]) -> Vec<Vec<u32>> {
    let set: HashSet<u32> = faces.iter().copied().collect();
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    for &f in faces {
        if !seen.insert(f) {
            continue;
        }
        let mut comp = vec![f];
        let mut q = VecDeque::from([f]);
        while let Some(x) = q.pop_front() {
            for &y in &adj[x as usize] {
                if set.contains(&y) && seen.insert(y) {
                    comp.push(y);
                    q.push_back(y);
                }
            }
        }
        out.push(comp);
    }
    out
}

/// Moves the pieces of the rest (`faces` not `taken`) that are cut off from its largest
/// component and touch the region into the region, and gives back as many region faces along
/// the largest component's border (most neighbours in the rest first), so both keep their
/// sizes. A few rounds; what cannot be traded (pieces of a mesh that is not connected) stays.
fn repair(adj: &[Vec<u32>], faces: &[u32], taken: &mut HashSet<u32>, member: &[bool]) {
    for _ in 0..4 {
        let rest: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|f| !taken.contains(f))
            .collect();
        let comps = components_of(adj, &rest);
        if comps.len() <= 1 {
            return;
        }
        let main = (0..comps.len())
            .max_by_key(|&i| (comps[i].len(), std::cmp::Reverse(i)))
            .unwrap_or(0);
        let touches = |c: &[u32], taken: &HashSet<u32>| {
            c.iter()
                .any(|&x| adj[x as usize].iter().any(|y| taken.contains(y)))
        };
        let mut moved = 0usize;
        for (i, c) in comps.iter().enumerate() {
            if i != main && touches(c, taken) {
                taken.extend(c.iter().copied());
                moved += c.len();
            }
        }
        if moved == 0 {
            return;
        }
        // Give back `moved` faces, growing the main component into the region.
        let mut frontier = Frontier::default();
        for &x in &comps[main] {
            for &y in &adj[x as usize] {
                if member[y as usize] && taken.contains(&y) {
                    frontier.touch(y);
                }
            }
        }
        while moved > 0 {
            let Some(x) = frontier.pop() else {
                break;
            };
            taken.remove(&x);
            moved -= 1;
            for &y in &adj[x as usize] {
                if member[y as usize] && taken.contains(&y) {
                    frontier.touch(y);
                }
            }
        }
        if moved > 0 {
            // The main component's border ran out (cannot happen while the region touches
            // it): keep the sizes by giving back any region faces.
            let back: Vec<u32> = faces
                .iter()
                .copied()
                .filter(|f| taken.contains(f))
                .take(moved)
                .collect();
            for f in back {
                taken.remove(&f);
            }
        }
    }
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

    /// A grid of quads (two triangles each): `n x n` quads.
    fn grid(n: u32) -> Vec<[u32; 3]> {
        let v = |i: u32, j: u32| i * (n + 1) + j;
        let mut t = Vec::new();
        for i in 0..n {
            for j in 0..n {
                t.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
                t.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
            }
        }
        t
    }

    /// Every bisection keeps both sides at their sizes and, on a connected surface, both sides
    /// contiguous down to sections of a few pairs.
    #[test]
    fn sections_of_connected_meshes_are_contiguous() {
        let t = grid(16); // 512 faces, 256 pairs: 4 levels
        let p = Partition::new(&t);
        assert_eq!(p.levels, 4);
        let c = p.components(&t);
        assert_eq!(&c[..2], &[1.0, 1.0], "{c:?}");
        assert!(c[2] <= 1.15 && c[3] < 1.2, "{c:?}");
        // The bunny (3674 faces): its sections down to 1/64 of the surface are contiguous.
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/meshes/bunny.obj");
        let bunny = crate::mesh::load_obj("bunny.obj", &std::fs::read(path).unwrap()).unwrap();
        let t = bunny.triangles();
        let p = Partition::new(t);
        let mut faces: Vec<u32> = p.order.iter().copied().filter(|&f| f != u32::MAX).collect();
        faces.sort_unstable();
        assert_eq!(faces, (0..t.len() as u32).collect::<Vec<_>>());
        let c = p.components(t);
        assert_eq!(&c[..3], &[1.0, 1.0, 1.0], "{c:?}");
        assert!(c.iter().all(|&x| x < 1.25), "{c:?}");
    }
}

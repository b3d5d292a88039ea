//! A sparse symmetric positive semi-definite solve by blocks: LDLᵀ in a least-degree
//! elimination order, for the joints' equality rows (one block per joint, at most
//! [`MAX_BLOCK`] rows). Two blocks couple when their joints share a moving body, so a
//! chain's matrix is block-tridiagonal and a tree's fills nothing once its leaves go
//! first: the least-degree order finds both, and bounds the fill of loops.
//!
//! f64 throughout: cheap at these sizes, and a light chain under a heavy load makes an
//! ill-conditioned matrix (its condition number was not measured; f32 was not tried).
//! Rows that depend on earlier ones (a body welded twice, rows of immovable bodies) meet
//! a pivot near zero and are dropped from the solve: the remaining rows hold them.

use std::cmp::Reverse;
use std::collections::{BTreeSet, BinaryHeap, HashMap};

/// The most rows in one block.
pub const MAX_BLOCK: usize = 6;

/// A dense block, row-major with stride [`MAX_BLOCK`].
pub type Block = [f64; MAX_BLOCK * MAX_BLOCK];

/// A pivot below this share of its row's diagonal marks the row as dependent.
const DEPENDENT: f64 = 1e-9;

#[inline]
fn at(r: usize, c: usize) -> usize {
    r * MAX_BLOCK + c
}

/// The structure of a factorisation: the elimination order and, for each node, the
/// blocks of L below it. Depends only on which nodes couple and their sizes.
#[derive(Clone, Debug, Default)]
pub struct BlockPattern {
    sizes: Vec<usize>,
    /// Node of each elimination position.
    order: Vec<u32>,
    /// Each node's later neighbours: `later[later_start[k]..later_start[k + 1]]`, as
    /// (node, index of the off-diagonal block that couples it with k).
    later_start: Vec<u32>,
    later: Vec<(u32, u32)>,
    /// For each node, the Schur updates its elimination makes: (q and p as places in its
    /// later neighbours, q eliminated after p or equal; the target: `Diag(p)` when p = q,
    /// else the block coupling q and p).
    update_start: Vec<u32>,
    updates: Vec<(u32, u32, Target)>,
    /// The node eliminated first of each off-diagonal block (its columns).
    first: Vec<u32>,
    /// Off-diagonal block index by (node, node), lower node first.
    index: HashMap<(u32, u32), u32>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    Diag(u32),
    Off(u32),
}

impl BlockPattern {
    /// The pattern for nodes of `sizes` rows (each 1..=MAX_BLOCK) coupled by `edges`.
    pub fn new(sizes: &[usize], edges: &[(u32, u32)]) -> Self {
        debug_assert!(sizes.iter().all(|&s| (1..=MAX_BLOCK).contains(&s)));
        let n = sizes.len();
        let mut adj: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); n];
        for &(a, b) in edges {
            if a != b {
                adj[a as usize].insert(b);
                adj[b as usize].insert(a);
            }
        }
        // Least degree first, ties by index (deterministic); stale heap entries skipped.
        let mut heap: BinaryHeap<Reverse<(usize, u32)>> = (0..n as u32)
            .map(|i| Reverse((adj[i as usize].len(), i)))
            .collect();
        let mut done = vec![false; n];
        let mut order = Vec::with_capacity(n);
        let mut later_sets: Vec<Vec<u32>> = vec![Vec::new(); n];
        while let Some(Reverse((degree, v))) = heap.pop() {
            let vi = v as usize;
            if done[vi] || degree != adj[vi].len() {
                continue;
            }
            done[vi] = true;
            order.push(v);
            let nbrs: Vec<u32> = std::mem::take(&mut adj[vi]).into_iter().collect();
            for &p in &nbrs {
                let set = &mut adj[p as usize];
                set.remove(&v);
                set.extend(nbrs.iter().copied().filter(|&q| q != p));
                heap.push(Reverse((set.len(), p)));
            }
            later_sets[vi] = nbrs;
        }
        debug_assert_eq!(order.len(), n, "every node eliminated once");
        let mut pos = vec![0u32; n];
        for (i, &v) in order.iter().enumerate() {
            pos[v as usize] = i as u32;
        }
        let mut pattern = Self {
            sizes: sizes.to_vec(),
            order,
            ..Self::default()
        };
        let mut index = HashMap::new();
        let key = |a: u32, b: u32| (a.min(b), a.max(b));
        pattern.later_start.push(0);
        for k in 0..n {
            let mut later = std::mem::take(&mut later_sets[k]);
            later.sort_unstable_by_key(|&p| pos[p as usize]);
            for p in later {
                let id = index.len() as u32;
                let old = index.insert(key(k as u32, p), id);
                debug_assert!(old.is_none(), "one block per coupled pair");
                pattern.first.push(k as u32);
                pattern.later.push((p, id));
            }
            pattern.later_start.push(pattern.later.len() as u32);
        }
        pattern.update_start.push(0);
        for k in 0..n {
            let later = pattern.later_of(k as u32).to_vec();
            for (ip, &(p, _)) in later.iter().enumerate() {
                for (iq, &(q, _)) in later.iter().enumerate().skip(ip) {
                    let target = if p == q {
                        Target::Diag(p)
                    } else {
                        // k's elimination made p and q neighbours, so p's own
                        // elimination (before q's) gave them a block.
                        Target::Off(index[&key(p, q)])
                    };
                    pattern.updates.push((iq as u32, ip as u32, target));
                }
            }
            pattern.update_start.push(pattern.updates.len() as u32);
        }
        pattern.index = index;
        pattern
    }

    fn later_of(&self, k: u32) -> &[(u32, u32)] {
        let k = k as usize;
        &self.later[self.later_start[k] as usize..self.later_start[k + 1] as usize]
    }

    /// The off-diagonal block coupling nodes `a` and `b` (stored with `a`'s rows when
    /// `a` is eliminated first, else transposed: see [`BlockMatrix::add_coupling`]).
    pub fn coupling(&self, a: u32, b: u32) -> Option<u32> {
        self.index.get(&(a.min(b), a.max(b))).copied()
    }

    /// Where the entries coupling `a`'s rows with `b`'s go (looked up once per pair, not
    /// per entry): see [`BlockMatrix::add_to`].
    pub fn slot(&self, a: u32, b: u32) -> Option<Slot> {
        let id = self.coupling(a, b)?;
        // Stored by the rows of the node eliminated later.
        Some(Slot {
            id,
            transposed: self.first[id as usize] == a,
        })
    }

    pub fn nodes(&self) -> usize {
        self.sizes.len()
    }

    /// How many off-diagonal blocks the factor holds (the matrix's couplings plus fill).
    pub fn fill(&self) -> usize {
        self.first.len()
    }
}

/// An off-diagonal block as one pair of nodes sees it.
#[derive(Clone, Copy, Debug)]
pub struct Slot {
    id: u32,
    transposed: bool,
}

/// A matrix on a [`BlockPattern`], then its factor. Off-diagonal block (k, p) holds the
/// rows of whichever of k and p is eliminated later, by the columns of the other.
#[derive(Clone, Debug, Default)]
pub struct BlockMatrix {
    diag: Vec<Block>,
    off: Vec<Block>,
    /// The largest diagonal entry of each node's rows before elimination.
    scale: Vec<[f64; MAX_BLOCK]>,
    /// Each node's row offset in a right-hand side.
    offsets: Vec<usize>,
    /// A node's blocks of L while it is eliminated.
    scratch: Vec<Block>,
}

impl BlockMatrix {
    /// A zero matrix on `pattern` (reusing this one's storage).
    pub fn reset(&mut self, pattern: &BlockPattern) {
        let n = pattern.nodes();
        self.diag.clear();
        self.diag.resize(n, [0.0; MAX_BLOCK * MAX_BLOCK]);
        self.off.clear();
        self.off
            .resize(pattern.fill(), [0.0; MAX_BLOCK * MAX_BLOCK]);
        self.offsets.clear();
        let mut at = 0;
        for &s in &pattern.sizes {
            self.offsets.push(at);
            at += s;
        }
        self.offsets.push(at);
    }

    /// Rows in all.
    pub fn rows(&self) -> usize {
        *self.offsets.last().unwrap_or(&0)
    }

    /// Adds `v` to entry (r, c) of node `k`'s diagonal block (and (c, r): give each
    /// unordered pair once, or the diagonal).
    pub fn add_diag(&mut self, k: u32, r: usize, c: usize, v: f64) {
        let d = &mut self.diag[k as usize];
        d[at(r, c)] += v;
        if r != c {
            d[at(c, r)] += v;
        }
    }

    /// Adds `v` to the entry coupling row `r` of node `a` with row `c` of node `b`.
    #[cfg(test)]
    pub fn add_coupling(
        &mut self,
        p: &BlockPattern,
        (a, r): (u32, usize),
        (b, c): (u32, usize),
        v: f64,
    ) {
        self.add_to(p.slot(a, b).expect("coupled nodes"), r, c, v);
    }

    /// Adds `v` to the entry of `slot` coupling row `r` of its first node with row `c` of
    /// its second.
    #[inline]
    pub fn add_to(&mut self, slot: Slot, r: usize, c: usize, v: f64) {
        let (r, c) = if slot.transposed { (c, r) } else { (r, c) };
        self.off[slot.id as usize][at(r, c)] += v;
    }

    /// Factors in place: LDLᵀ by blocks, each D block kept as its (pseudo-)inverse.
    pub fn factor(&mut self, pattern: &BlockPattern) {
        self.scale.clear();
        for (k, d) in self.diag.iter().enumerate() {
            let mut s = [0.0; MAX_BLOCK];
            for (r, s) in s.iter_mut().enumerate().take(pattern.sizes[k]) {
                *s = d[at(r, r)].abs();
            }
            self.scale.push(s);
        }
        let mut l = std::mem::take(&mut self.scratch);
        for &k in &pattern.order {
            let ku = k as usize;
            let sk = pattern.sizes[ku];
            let inv = pseudo_inverse(&self.diag[ku], sk, &self.scale[ku]);
            self.diag[ku] = inv;
            let later = pattern.later_of(k);
            // L(p, k) = A(p, k) · D(k)⁻¹, kept aside while the updates read A(p, k).
            l.clear();
            for &(p, id) in later {
                l.push(mul(
                    &self.off[id as usize],
                    &inv,
                    pattern.sizes[p as usize],
                    sk,
                    sk,
                ));
            }
            let start = pattern.update_start[ku] as usize;
            let end = pattern.update_start[ku + 1] as usize;
            for &(iq, ip, target) in &pattern.updates[start..end] {
                let ((q, _), (p, bp)) = (later[iq as usize], later[ip as usize]);
                // A(q, p) −= L(q, k) · A(p, k)ᵀ.
                let lq = &l[iq as usize];
                let apk = self.off[bp as usize];
                let (sq, sp) = (pattern.sizes[q as usize], pattern.sizes[p as usize]);
                let t = match target {
                    Target::Diag(d) => &mut self.diag[d as usize],
                    Target::Off(o) => &mut self.off[o as usize],
                };
                for r in 0..sq {
                    for c in 0..sp {
                        let mut s = 0.0;
                        for m in 0..sk {
                            s += lq[at(r, m)] * apk[at(c, m)];
                        }
                        t[at(r, c)] -= s;
                    }
                }
            }
            for (i, &(_, id)) in later.iter().enumerate() {
                self.off[id as usize] = l[i];
            }
        }
        self.scratch = l;
    }

    /// Solves in place: `x` holds the right-hand side and leaves with the solution.
    pub fn solve(&self, pattern: &BlockPattern, x: &mut [f64]) {
        debug_assert_eq!(x.len(), self.rows());
        let mut tmp = [0.0; MAX_BLOCK];
        for &k in &pattern.order {
            let (ok, sk) = (self.offsets[k as usize], pattern.sizes[k as usize]);
            for &(p, id) in pattern.later_of(k) {
                let (op, sp) = (self.offsets[p as usize], pattern.sizes[p as usize]);
                let lb = &self.off[id as usize];
                for r in 0..sp {
                    let mut s = 0.0;
                    for c in 0..sk {
                        s += lb[at(r, c)] * x[ok + c];
                    }
                    x[op + r] -= s;
                }
            }
        }
        for (k, inv) in self.diag.iter().enumerate() {
            let (ok, sk) = (self.offsets[k], pattern.sizes[k]);
            for (r, t) in tmp.iter_mut().enumerate().take(sk) {
                *t = (0..sk).map(|c| inv[at(r, c)] * x[ok + c]).sum();
            }
            x[ok..ok + sk].copy_from_slice(&tmp[..sk]);
        }
        for &k in pattern.order.iter().rev() {
            let (ok, sk) = (self.offsets[k as usize], pattern.sizes[k as usize]);
            for &(p, id) in pattern.later_of(k) {
                let (op, sp) = (self.offsets[p as usize], pattern.sizes[p as usize]);
                let lb = &self.off[id as usize];
                for c in 0..sk {
                    let mut s = 0.0;
                    for r in 0..sp {
                        s += lb[at(r, c)] * x[op + r];
                    }
                    x[ok + c] -= s;
                }
            }
        }
    }
}

/// `a` (rows × inner) times `b` (inner × cols).
fn mul(a: &Block, b: &Block, rows: usize, inner: usize, cols: usize) -> Block {
    let mut out = [0.0; MAX_BLOCK * MAX_BLOCK];
    for r in 0..rows {
        for c in 0..cols {
            out[at(r, c)] = (0..inner).map(|m| a[at(r, m)] * b[at(m, c)]).sum();
        }
    }
    out
}

/// The inverse of a symmetric positive semi-definite block of size `n`, by LDLᵀ; a row
/// whose pivot falls below [`DEPENDENT`] of its `scale` counts as dependent and gets
/// nothing (the pseudo-inverse of the rest).
fn pseudo_inverse(a: &Block, n: usize, scale: &[f64; MAX_BLOCK]) -> Block {
    let mut l = [0.0; MAX_BLOCK * MAX_BLOCK];
    let mut d = [0.0; MAX_BLOCK];
    for j in 0..n {
        let mut dj = a[at(j, j)];
        for m in 0..j {
            dj -= l[at(j, m)] * l[at(j, m)] * d[m];
        }
        let live = dj > DEPENDENT * scale[j] && dj > 0.0;
        d[j] = if live { dj } else { 0.0 };
        l[at(j, j)] = 1.0;
        for i in j + 1..n {
            let mut s = a[at(i, j)];
            for m in 0..j {
                s -= l[at(i, m)] * l[at(j, m)] * d[m];
            }
            l[at(i, j)] = if live { s / dj } else { 0.0 };
        }
    }
    // inv = L⁻ᵀ D⁺ L⁻¹, column by column.
    let mut inv = [0.0; MAX_BLOCK * MAX_BLOCK];
    for col in 0..n {
        let mut y = [0.0; MAX_BLOCK];
        for i in 0..n {
            let mut s = if i == col { 1.0 } else { 0.0 };
            for m in 0..i {
                s -= l[at(i, m)] * y[m];
            }
            y[i] = s;
        }
        for i in 0..n {
            y[i] = if d[i] > 0.0 { y[i] / d[i] } else { 0.0 };
        }
        for i in (0..n).rev() {
            let mut s = y[i];
            for m in i + 1..n {
                s -= l[at(m, i)] * y[m];
            }
            y[i] = s;
        }
        for i in 0..n {
            inv[at(i, col)] = y[i];
        }
    }
    inv
}

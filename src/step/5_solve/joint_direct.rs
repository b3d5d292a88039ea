//! The joints' equality rows (the anchors together, no turn, no slide across, a rigid
//! distance) solved all at once and exactly, each pass: a sparse LDLᵀ of their
//! effective-mass matrix A = J·M⁻¹·Jᵀ (`math::block_ldl`). Limits, motors, springs and
//! ropes stay soft Gauss–Seidel rows (`joint.rs`): they switch on and off, which a factor
//! cannot follow.
//!
//! Why: one Gauss–Seidel pass moves a load about one link along a chain, so light links
//! under a heavy weight never converge in the few passes a substep has, and a soft joint
//! is a spring tuned to its light links' mass: a 30-link chain under a ball a hundred
//! times heavier stretched 14.5 % at 4 substeps. Solved together the rows hold the whole
//! chain in one pass.
//!
//! The soft step carries over exactly. A lone block solved Gauss–Seidel is
//! Δλ = −s·K⁻¹(J·v + β·C) − i·λ (`Softness`); that is (1 + c)·K·Δλ = −(J·v + β·C) − c·K·λ
//! with c = i/s. Here K is each group's own block of A and the system is
//! (A + c·D)·Δλ = −(J·v + β·C) − c·D·λ with D those blocks: a joint alone gets the
//! impulse it got before, and coupled joints the soft solution of all of them. The relax
//! pass (c = 0, β = 0) brings every row's velocity to zero. Solved exactly, the soft rows
//! are an implicit spring stable at any stiffness, so their frequency may pass the
//! quarter of the substep rate Gauss–Seidel rows keep to (`HELD_MAX_RATE`).

use bevy::prelude::*;

use super::joint::{Now, now, rotation_error};
use crate::math::block_ldl::{BlockMatrix, BlockPattern, MAX_BLOCK};
use crate::world::{JointConstraint, JointRows, STATIC, SolverBody, body};

/// The share of each group's own block added to the matrix, but not to the right-hand
/// side: a damped step (Levenberg–Marquardt's), which the passes and substeps converge
/// through. Rows that depend on each other in exact arithmetic (a chain pulled straight
/// between two fixed points: the sum of its rows along the chain) are only nearly so
/// from f32 rows, and solved undamped they took impulses of round-off over a pivot of
/// round-off: a taut bridge reported 52 kN in its first step and flew apart when a crate
/// stepped on it. Damped, such an impulse stays near its round-off, while a genuine
/// mode loses little of its step (one whose pivot is 1e-5 of its diagonal, a tenth; the
/// next passes and substeps make it up).
const DAMPING: f32 = 1e-6;

/// One equality row: its Jacobian on A and on B (linear, angular parts; J·v is their dot
/// products with the bodies' velocities), the error its bias closes (m or rad), and its
/// accumulated impulse this substep (N·s or N·m·s).
#[derive(Clone, Copy, Debug, Default)]
struct Row {
    la: Vec3,
    aa: Vec3,
    lb: Vec3,
    ab: Vec3,
    error: f32,
    lambda: f32,
}

/// Where a group of rows keeps its impulse in the joint.
#[derive(Clone, Copy, Debug)]
enum Group {
    /// The anchors together: `linear`, world axes.
    Point,
    /// No relative turn: `angular`, world axes.
    Turns,
    /// No turn across a hinge's axis: `angular` along the two directions.
    HingeTurns(Vec3, Vec3),
    /// No offset across a slider's axis: `linear` along the two directions.
    SlideAcross(Vec3, Vec3),
    /// A rigid distance: `axial[0]`.
    Distance,
}

/// One joint with equality rows: a node of the factor.
#[derive(Clone, Copy, Debug)]
struct Node {
    joint: u32,
    /// Its bodies ([`STATIC`] for the world).
    a: u32,
    b: u32,
    /// Whether each can move (a kinematic body's velocity counts, but it couples nothing).
    moves: [bool; 2],
    first_row: u32,
    groups: [Option<Group>; 2],
    /// The soft coupling c = i/s this stage (0 in the relax pass).
    c: f32,
}

/// The equality rows of this step's joints and their factor, rebuilt each stage (the
/// anchors turn with the bodies between the solve and the relax pass).
#[derive(Default)]
pub(crate) struct JointSystem {
    /// Each node's (a, b, rows): the pattern is kept while these stay the same.
    key: Vec<(u32, u32, u8)>,
    pattern: BlockPattern,
    matrix: BlockMatrix,
    nodes: Vec<Node>,
    rows: Vec<Row>,
    /// Each group's own block of A (D), for c·D·λ: row-major, stride MAX_BLOCK.
    own: Vec<[f32; MAX_BLOCK * MAX_BLOCK]>,
    rhs: Vec<f64>,
    /// Scratch for the pattern: (body, node) pairs.
    by_body: Vec<(u32, u32)>,
}

fn moves(b: &SolverBody) -> bool {
    b.inv_mass > 0.0 || b.inv_inertia != Mat3::ZERO
}

/// The equality groups of `j`, and the rows they start with, at `f`.
fn groups(j: &JointConstraint, f: &Now) -> [Option<Group>; 2] {
    match j.rows {
        JointRows::Fixed => [Some(Group::Point), Some(Group::Turns)],
        JointRows::Spherical => [Some(Group::Point), None],
        JointRows::Revolute => {
            let (t1, t2) = f.axis.any_orthonormal_pair();
            [Some(Group::Point), Some(Group::HingeTurns(t1, t2))]
        }
        JointRows::Prismatic => {
            let (t1, t2) = f.axis.any_orthonormal_pair();
            [Some(Group::SlideAcross(t1, t2)), Some(Group::Turns)]
        }
        JointRows::Distance => {
            let rigid = j.limits.is_some_and(|(lo, hi)| lo >= hi);
            [rigid.then_some(Group::Distance), None]
        }
    }
}

/// A linear row along unit `d` from arms `arm_a`, `arm_b`; an angular row about `d`.
fn linear_row(arm_a: Vec3, arm_b: Vec3, d: Vec3, error: f32, lambda: f32) -> Row {
    Row {
        la: -d,
        aa: -arm_a.cross(d),
        lb: d,
        ab: arm_b.cross(d),
        error,
        lambda,
    }
}

fn angular_row(d: Vec3, error: f32, lambda: f32) -> Row {
    Row {
        aa: -d,
        ab: d,
        error,
        lambda,
        ..Row::default()
    }
}

/// `group`'s rows for `j` at `f`, with its accumulated impulses.
fn push_rows(
    rows: &mut Vec<Row>,
    group: Group,
    j: &JointConstraint,
    a: &SolverBody,
    b: &SolverBody,
    f: &Now,
) {
    let axes = [Vec3::X, Vec3::Y, Vec3::Z];
    match group {
        Group::Point => {
            for (k, e) in axes.into_iter().enumerate() {
                rows.push(linear_row(f.ra, f.rb, e, f.d[k], j.linear[k]));
            }
        }
        Group::Turns => {
            let (_, e) = rotation_error(j, a, b);
            for (k, d) in axes.into_iter().enumerate() {
                rows.push(angular_row(d, e[k], j.angular[k]));
            }
        }
        Group::HingeTurns(t1, t2) => {
            let (_, e) = rotation_error(j, a, b);
            for t in [t1, t2] {
                rows.push(angular_row(t, t.dot(e), t.dot(j.angular)));
            }
        }
        Group::SlideAcross(t1, t2) => {
            let arm_a = f.ra + f.d;
            for t in [t1, t2] {
                rows.push(linear_row(arm_a, f.rb, t, t.dot(f.d), t.dot(j.linear)));
            }
        }
        Group::Distance => {
            let length = f.d.length();
            let n = if length > 1e-6 { f.d / length } else { f.axis };
            let lo = j.limits.map_or(0.0, |l| l.0);
            rows.push(linear_row(f.ra, f.rb, n, length - lo, j.axial[0]));
        }
    }
}

/// J_r·M⁻¹·J_sᵀ through one body, with `r`'s and `s`'s parts on it.
fn through(body: &SolverBody, (lr, ar): (Vec3, Vec3), (ls, as_): (Vec3, Vec3)) -> f32 {
    body.inv_mass * lr.dot(ls) + ar.dot(body.inv_inertia * as_)
}

impl Row {
    fn on(&self, side_b: bool) -> (Vec3, Vec3) {
        if side_b {
            (self.lb, self.ab)
        } else {
            (self.la, self.aa)
        }
    }
}

impl Group {
    fn rows(self) -> usize {
        match self {
            Group::Point | Group::Turns => 3,
            Group::HingeTurns(..) | Group::SlideAcross(..) => 2,
            Group::Distance => 1,
        }
    }
}

impl JointSystem {
    /// Builds the rows at the bodies' current pose and factors their matrix: softly with
    /// `use_bias` (the solve), rigidly without (the relax pass).
    pub fn prepare(&mut self, bodies: &[SolverBody], joints: &[JointConstraint], use_bias: bool) {
        self.nodes.clear();
        self.rows.clear();
        for (i, j) in joints.iter().enumerate() {
            let (a, b) = (body(bodies, j.a), body(bodies, j.b));
            let f = now(j, &a, &b);
            let groups = groups(j, &f);
            if groups[0].is_none() {
                continue;
            }
            let first_row = self.rows.len() as u32;
            for g in groups.into_iter().flatten() {
                push_rows(&mut self.rows, g, j, &a, &b, &f);
            }
            let s = &j.held;
            let soft = use_bias && s.mass_scale > 0.0;
            let c = if soft {
                s.impulse_scale / s.mass_scale
            } else {
                0.0
            };
            self.nodes.push(Node {
                joint: i as u32,
                a: j.a,
                b: j.b,
                moves: [j.a != STATIC && moves(&a), j.b != STATIC && moves(&b)],
                first_row,
                groups,
                c,
            });
        }
        self.refresh_pattern();
        self.fill(bodies);
        self.matrix.factor(&self.pattern);
    }

    /// A new pattern when the joints' bodies or rows changed.
    fn refresh_pattern(&mut self) {
        let key = (0..self.nodes.len()).map(|k| {
            let n = &self.nodes[k];
            let side = |i: u32, moves: bool| if moves { i } else { STATIC };
            (
                side(n.a, n.moves[0]),
                side(n.b, n.moves[1]),
                rows_of(&self.nodes, self.rows.len(), k).len() as u8,
            )
        });
        if key.clone().eq(self.key.iter().copied()) {
            return;
        }
        self.key = key.collect();
        self.by_body.clear();
        for (k, &(a, b, _)) in self.key.iter().enumerate() {
            for i in [a, b] {
                if i != STATIC {
                    self.by_body.push((i, k as u32));
                }
            }
        }
        self.by_body.sort_unstable();
        let mut edges = Vec::new();
        for run in self.by_body.chunk_by(|x, y| x.0 == y.0) {
            for (i, &(_, x)) in run.iter().enumerate() {
                edges.extend(
                    run[i + 1..]
                        .iter()
                        .filter(|y| y.1 != x)
                        .map(|&(_, y)| (x, y)),
                );
            }
        }
        let sizes: Vec<usize> = self.key.iter().map(|k| k.2 as usize).collect();
        self.pattern = BlockPattern::new(&sizes, &edges);
    }

    /// A = J·M⁻¹·Jᵀ into the matrix: each node's own block, then the couplings.
    fn fill(&mut self, bodies: &[SolverBody]) {
        let Self {
            matrix,
            pattern,
            nodes,
            rows,
            own,
            ..
        } = self;
        matrix.reset(pattern);
        own.clear();
        let rows_of = |k: usize| rows_of(nodes, rows.len(), k);
        for (k, n) in nodes.iter().enumerate() {
            let node_rows = &rows[rows_of(k)];
            let first_group = n.groups[0].map_or(0, Group::rows);
            let mut block = [0.0f32; MAX_BLOCK * MAX_BLOCK];
            for (r, x) in node_rows.iter().enumerate() {
                for (s, y) in node_rows.iter().enumerate().skip(r) {
                    let mut v = 0.0;
                    for (i, side_b) in [(n.a, false), (n.b, true)] {
                        if i != STATIC {
                            v += through(&bodies[i as usize], x.on(side_b), y.on(side_b));
                        }
                    }
                    // D: A's blocks within a group (the blocks the soft step knows).
                    let same_group = (r < first_group) == (s < first_group);
                    if same_group {
                        (block[r * MAX_BLOCK + s], block[s * MAX_BLOCK + r]) = (v, v);
                    }
                    let soft = if same_group { 1.0 + n.c + DAMPING } else { 1.0 };
                    matrix.add_diag(k as u32, r, s, (v * soft) as f64);
                }
            }
            own.push(block);
        }
        // Couplings through a shared body.
        for run in self.by_body.chunk_by(|x, y| x.0 == y.0) {
            let i = run[0].0;
            let body = &bodies[i as usize];
            for (m, &(_, x)) in run.iter().enumerate() {
                for &(_, y) in run[m + 1..].iter().filter(|y| y.1 != x) {
                    let (nx, ny) = (&nodes[x as usize], &nodes[y as usize]);
                    let slot = pattern.slot(x, y).expect("nodes on one body couple");
                    for (r, rx) in rows[rows_of(x as usize)].iter().enumerate() {
                        for (s, ry) in rows[rows_of(y as usize)].iter().enumerate() {
                            let v = through(body, rx.on(nx.b == i), ry.on(ny.b == i));
                            matrix.add_to(slot, r, s, v as f64);
                        }
                    }
                }
            }
        }
    }

    /// One pass: every equality row's impulse solved together, applied, and kept in the
    /// joints.
    pub fn solve(
        &mut self,
        bodies: &mut [SolverBody],
        joints: &mut [JointConstraint],
        use_bias: bool,
    ) {
        if self.nodes.is_empty() {
            return;
        }
        self.rhs.clear();
        for (k, n) in self.nodes.iter().enumerate() {
            let (a, b) = (body(bodies, n.a), body(bodies, n.b));
            let bias_rate = if use_bias {
                joints[n.joint as usize].held.bias_rate
            } else {
                0.0
            };
            let rows = &self.rows[rows_of(&self.nodes, self.rows.len(), k)];
            let own = &self.own[k];
            for (r, row) in rows.iter().enumerate() {
                let jv = row.la.dot(a.v) + row.aa.dot(a.w) + row.lb.dot(b.v) + row.ab.dot(b.w);
                let d_lambda: f32 = (rows.iter().enumerate())
                    .map(|(s, y)| own[r * MAX_BLOCK + s] * y.lambda)
                    .sum();
                self.rhs
                    .push(-(jv + bias_rate * row.error + n.c * d_lambda) as f64);
            }
        }
        self.matrix.solve(&self.pattern, &mut self.rhs);
        for (k, n) in self.nodes.iter().enumerate() {
            let range = rows_of(&self.nodes, self.rows.len(), k);
            for r in range.clone() {
                let dl = self.rhs[r] as f32;
                let row = &mut self.rows[r];
                row.lambda += dl;
                for (i, side_b) in [(n.a, false), (n.b, true)] {
                    if i != STATIC {
                        let (l, w) = row.on(side_b);
                        let body = &mut bodies[i as usize];
                        body.v += body.inv_mass * l * dl;
                        body.w += body.inv_inertia * w * dl;
                    }
                }
            }
            keep_impulses(&mut joints[n.joint as usize], n, &self.rows[range]);
        }
    }
}

/// Node `k`'s rows among `total`: from its first to the next node's.
fn rows_of(nodes: &[Node], total: usize, k: usize) -> std::ops::Range<usize> {
    let end = nodes.get(k + 1).map_or(total, |n| n.first_row as usize);
    nodes[k].first_row as usize..end
}

/// The rows' impulses back into the joint's accumulators.
fn keep_impulses(j: &mut JointConstraint, n: &Node, rows: &[Row]) {
    let mut rows = rows.iter().map(|r| r.lambda);
    let mut next = || rows.next().unwrap_or(0.0);
    for g in n.groups.into_iter().flatten() {
        match g {
            Group::Point => j.linear = Vec3::new(next(), next(), next()),
            Group::Turns => j.angular = Vec3::new(next(), next(), next()),
            Group::HingeTurns(t1, t2) => j.angular = t1 * next() + t2 * next(),
            Group::SlideAcross(t1, t2) => j.linear = t1 * next() + t2 * next(),
            Group::Distance => j.axial[0] = next(),
        }
    }
}

//! The `smooth` corner mode: every junction blended inside the path tolerance, runs of short
//! segments smoothed as one curve, and the result grouped into chains that one feed profile runs.
//!
//! Three streaming stages, each holding back at most one item:
//! 1. Vertices → spans. A vertex between two short G1 lines that turn gently is *smooth*: the
//!    circle through it and its two neighbours gives its tangent and curvature, and the span
//!    between two such vertices is the quintic Hermite matching both (a compressor in the manner
//!    of the 840D's COMPCURV, but interpolating the programmed points). A span is kept only if
//!    its Bézier control points — hence the whole span — lie within half the tolerance of its
//!    programmed chord; otherwise it stays the programmed line.
//! 2. Junctions (junction.rs). Where two spans do not already join with equal first and second derivatives,
//!    both are cut back by d and a quintic Hermite transition (hermite.rs; eq. 45–52 for two
//!    lines) joins them: d from the apex distance of eq. 52 at the tolerance, at most half of
//!    each programmed span, shrunk until the transition stays within the tolerance of the
//!    programmed geometry (eq. 52 between lines; a sampled check with a guaranteed guard
//!    between samples otherwise), and a stop instead where the transition would be slower. Only exact stop (G61), a reversal beyond `REVERSAL_COS` and the
//!    program's stops stop the path.
//! 3. Chains. Consecutive pieces of similar speed class join one chain (chain.rs); its limits
//!    come from guaranteed bounds of its pieces' derivatives (`curve_limits`), so every axis keeps
//!    its velocity, acceleration and jerk limit for any speed change the feed law makes inside.

use super::chain::{piece_limits, Chain, Curve, CurveLimits, Piece};
use super::hermite::{bezier, Hermite, Jet, BOUND_PIECES};
use super::junction::transition;
use super::source_map;
use super::tolerance::{COLLINEAR_SIN2, JOINT_D1_EPS, JOINT_D2_EPS, KNOT_SLACK, MIN_LENGTH};
use super::{line_limits, max_bounds, PathBlock, Segment};
use crate::config::Machine;
use crate::feed::bands::{Banded, Bands};
use crate::feed::{scurve7_banded, Limits, ProfileKind};
use crate::geometry::{add, cross, dot, norm, scale, sub, unit, Line};
use crate::geometry::{distance_to_segment, Source};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Largest turning angle at a smooth vertex (cos), and longest segment smoothed.
const SMOOTH_MIN_COS: f64 = 0.866_025_403_784_438_6; // 30°
const SMOOTH_MAX_SEGMENT: f64 = 5e-3;
/// Share of the tolerance a fitted span may use: a span that needs all of it fits badly (its
/// curvature swings), and splitting it is faster to run.
const SPAN_SHARE: f64 = 0.7;
/// Parts of each chord's range whose control points are checked.
const CHECK_PIECES: usize = 4;
/// Knot spacing of the fitted spans (m): long enough that rounding of the programmed points
/// does not show as jerk, short enough to follow curvature.
const KNOT_LENGTH: f64 = 2e-3;
/// Moves held at most in one run before its spans are fitted.
const RUN_MAX: usize = 1024;
/// Pieces at most in one chain.
const CHAIN_MAX_PIECES: usize = 512;

/// A programmed move as the builder receives it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Move {
    pub source: Source,
    pub line: u32,
    pub feed: f64,
    /// Path tolerance at the junction after this move (G64 P or the machine's).
    pub tolerance: f64,
    /// G61 on this move: stop at both its ends.
    pub exact: bool,
}

/// A vertex's tangent and curvature when it is smooth.
type VertexJet = Option<(Vec3, Vec3)>;

/// Tangent and curvature vector at `b` of the circle through a, b, c (travelled a → b → c).
fn circle_jet(a: Vec3, b: Vec3, c: Vec3) -> (Vec3, Vec3) {
    let (u, w) = (sub(a, b), sub(c, b));
    let n = cross(u, w);
    let n2 = dot(n, n);
    let chord = sub(c, a);
    if n2 <= COLLINEAR_SIN2 * dot(u, u) * dot(w, w) {
        return (unit(chord), [0.0; 3]);
    }
    // Circumcentre relative to b: ((|u|²·w − |w|²·u) × n) / (2|n|²).
    let o = scale(cross(sub(scale(w, dot(u, u)), scale(u, dot(w, w))), n), 0.5 / n2);
    let k = scale(o, 1.0 / dot(o, o));
    let on = unit(o);
    let t = unit(sub(chord, scale(on, dot(chord, on))));
    (t, k)
}

/// Jet at the end point `a` of the circle through a, b, c (travelled from a towards b; with
/// `reverse`, arriving at a from b).
fn circle_jet_at_end(a: Vec3, b: Vec3, c: Vec3, reverse: bool) -> (Vec3, Vec3) {
    let (t_mid, k_mid) = circle_jet(a, b, c);
    let toward = if reverse { sub(a, b) } else { sub(b, a) };
    if dot(k_mid, k_mid) == 0.0 {
        // Collinear points: the chord's direction, pointing the way the path runs at `a`.
        let t = if dot(t_mid, toward) < 0.0 {
            scale(t_mid, -1.0)
        } else {
            t_mid
        };
        return (t, k_mid);
    }
    let o = add(b, scale(k_mid, 1.0 / dot(k_mid, k_mid)));
    let r = sub(o, a);
    let k = scale(r, 1.0 / dot(r, r));
    let rn = unit(r);
    (unit(sub(toward, scale(rn, dot(toward, rn)))), k)
}

/// A span on its way through stage 2: the piece left of it, the programmed moves at its ends and
/// where the moves after the first begin on it (source_map.rs).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Span {
    pub(super) piece: Piece,
    pub(super) first: Move,
    pub(super) last: Move,
    pub(super) marks: Vec<(f64, u32)>,
    /// The curve's own limits once computed (junction.rs needs them before stage 3 does; a
    /// cache, recomputed after a restore).
    #[serde(skip)]
    pub(super) own: Option<CurveLimits>,
}

impl Span {
    fn single(curve: Curve, mv: Move) -> Span {
        Span {
            piece: Piece::whole(curve, mv.line),
            first: mv,
            last: mv,
            marks: Vec::new(),
            own: None,
        }
    }
}

/// The smooth-mode builder (see the module comment).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SmoothBuilder {
    /// Stage 1: the run of moves whose inner vertices are smooth, and the jet at its first vertex
    /// (None: a corner, or the start).
    run: Vec<Move>,
    run_jet: VertexJet,
    /// Stage 2: the span waiting for its junction with the next.
    held: Option<Span>,
    /// Stage 3: the chain being filled, its pieces' bound cells, feed and speed class.
    chain: Chain,
    cells: Vec<[Vec3; 3]>,
    chain_feed: f64,
    chain_class: f64,
    /// Time the chain's pieces lose to running at `chain_class` (`loss_if_joined`).
    chain_loss: f64,
    /// The limits and bands its first piece ramps within (`joining_pays`).
    chain_ramps: Option<(Limits, Bands)>,
    chain_straight: bool,
    /// Largest |p'| over the chain: the feed in the chain parameter is the feed over it.
    chain_sigma: f64,
    /// The limits of the chain's only piece, while it has one (computed when it was added).
    chain_single: Option<CurveLimits>,
}

impl SmoothBuilder {
    /// A restored builder: its moves, held span and chain checked (the chain may be empty).
    pub fn check_state(&self) -> Result<(), String> {
        use super::check::{one_piece, pieces, programmed};
        self.run.iter().try_for_each(programmed)?;
        if let Some(s) = &self.held {
            one_piece(&s.piece)?;
            programmed(&s.first)?;
            programmed(&s.last)?;
        }
        pieces(&self.chain)
    }

    pub fn new() -> SmoothBuilder {
        SmoothBuilder {
            run: Vec::new(),
            run_jet: None,
            held: None,
            chain: Chain::default(),
            cells: Vec::new(),
            chain_feed: 0.0,
            chain_class: 0.0,
            chain_loss: 0.0,
            chain_ramps: None,
            chain_straight: true,
            chain_sigma: 1.0,
            chain_single: None,
        }
    }

    /// Take one programmed move.
    pub fn push(&mut self, mv: Move, m: &Machine, out: &mut Vec<PathBlock>) {
        if let Some(last) = self.run.last().copied() {
            if smooth_vertex(&last, &mv) {
                if self.run.len() >= RUN_MAX {
                    self.flush_run(true, m, out);
                }
            } else {
                self.flush_run(false, m, out);
                if last.exact || mv.exact {
                    self.flush_held(m, out);
                }
            }
        }
        self.run.push(mv);
    }

    /// Stop at the end of everything received (dwell, M0, program end).
    pub fn stop(&mut self, m: &Machine, out: &mut Vec<PathBlock>) {
        self.flush_run(false, m, out);
        self.flush_held(m, out);
    }

    /// Stage 1: fit the run with Hermite spans between knots about `KNOT_LENGTH` apart; with
    /// `keep_tail`, the last span stays in the run (its first knot's jet carried) for the moves
    /// still to come.
    fn flush_run(&mut self, keep_tail: bool, m: &Machine, out: &mut Vec<PathBlock>) {
        let run = std::mem::take(&mut self.run);
        let jet0 = self.run_jet.take();
        let Some(first) = run.first().copied() else { return };
        if run.len() == 1 && jet0.is_none() {
            let curve = match first.source {
                Source::Arc(a) => Curve::Arc(a),
                Source::Line(l) => Curve::Line(l),
            };
            self.junction(Span::single(curve, first), m, out);
            return;
        }
        let verts: Vec<Vec3> = std::iter::once(start_of(&first))
            .chain(run.iter().map(end_of))
            .collect();
        let knots = choose_knots(&run);
        let mut jets: Vec<VertexJet> = vec![None; knots.len()];
        for j in 1..knots.len() - 1 {
            jets[j] = Some(circle_jet(
                verts[knots[j - 1]],
                verts[knots[j]],
                verts[knots[j + 1]],
            ));
        }
        // The run's ends continue the circle through their three nearest knots (or vertices), so
        // curvature does not fall to zero there; the transition to the neighbour takes over.
        let n = knots.len();
        let ends = if n >= 3 {
            Some((
                [knots[0], knots[1], knots[2]],
                [knots[n - 1], knots[n - 2], knots[n - 3]],
            ))
        } else if run.len() >= 2 {
            let mid = run.len() / 2;
            Some(([0, mid, run.len()], [run.len(), mid, 0]))
        } else {
            None
        };
        if let Some((s, e)) = ends {
            jets[0] = Some(circle_jet_at_end(verts[s[0]], verts[s[1]], verts[s[2]], false));
            jets[n - 1] = Some(circle_jet_at_end(verts[e[0]], verts[e[1]], verts[e[2]], true));
        }
        if jet0.is_some() {
            jets[0] = jet0;
        }
        let spans = if keep_tail && knots.len() >= 3 {
            knots.len() - 2
        } else {
            knots.len() - 1
        };
        for j in 0..spans {
            self.fit(&run[knots[j]..knots[j + 1]], jets[j], jets[j + 1], m, out);
        }
        if spans < knots.len() - 1 {
            self.run = run[knots[spans]..].to_vec();
            self.run_jet = jets[spans];
        }
    }

    /// One Hermite span over `moves` from jet `a` to jet `b` if it stays within the tolerance
    /// of every programmed chord (guaranteed by the control points of the curve over
    /// each chord's parameter range); else split at the middle vertex, down to single lines.
    fn fit(&mut self, moves: &[Move], a: VertexJet, b: VertexJet, m: &Machine, out: &mut Vec<PathBlock>) {
        let (first, last) = (moves[0], moves[moves.len() - 1]);
        let line_of = |mv: &Move| match mv.source {
            Source::Line(l) => l,
            Source::Arc(_) => unreachable!("runs of more than one move hold lines only"),
        };
        if moves.len() == 1 && a.is_none() && b.is_none() {
            self.junction(Span::single(Curve::Line(line_of(&first)), first), m, out);
            return;
        }
        let jet = |p: Vec3, v: VertexJet, mv: &Move| {
            let (t, k) = v.unwrap_or((line_of(mv).direction(), [0.0; 3]));
            Jet { p, d1: t, d2: k }
        };
        let lambda: f64 = moves.iter().map(|mv| mv.source.length()).sum();
        let h = Hermite::new(
            jet(start_of(&first), a, &first),
            jet(end_of(&last), b, &last),
            lambda,
        );
        let mut u = 0.0;
        let mut inside = true;
        let mut jet_u = h.jet(0.0);
        'moves: for mv in moves {
            let l = line_of(mv);
            let ub = (u + l.length()).min(lambda);
            // The curve over the chord's range, in `CHECK_PIECES` parts: each part lies in the
            // hull of its control points, which come close to the curve as the parts shrink.
            let step = (ub - u) / CHECK_PIECES as f64;
            for k in 1..=CHECK_PIECES {
                let u1 = if k == CHECK_PIECES {
                    ub
                } else {
                    u + step * k as f64
                };
                let jet_next = h.jet(u1);
                inside = bezier(&jet_u, &jet_next, step)
                    .iter()
                    .all(|&c| distance_to_segment(c, l.start, l.end) <= SPAN_SHARE * mv.tolerance);
                jet_u = jet_next;
                if !inside {
                    break 'moves;
                }
            }
            u = ub;
        }
        if inside {
            let span = Span {
                piece: Piece::whole(Curve::Hermite(h), first.line),
                first,
                last,
                marks: source_map::span_marks(moves),
                own: None,
            };
            self.junction(span, m, out);
        } else if moves.len() == 1 {
            self.junction(Span::single(Curve::Line(line_of(&first)), first), m, out);
        } else {
            let mid = moves.len() / 2;
            let v = |i: usize| {
                if i == 0 {
                    start_of(&moves[0])
                } else {
                    end_of(&moves[i - 1])
                }
            };
            let jm = Some(circle_jet(v(0), v(mid), v(moves.len())));
            self.fit(&moves[..mid], a, jm, m, out);
            self.fit(&moves[mid..], jm, b, m, out);
        }
    }

    /// Stage 2: join `next` to the held span.
    fn junction(&mut self, mut next: Span, m: &Machine, out: &mut Vec<PathBlock>) {
        let Some(mut held) = self.held.take() else {
            self.held = Some(next);
            return;
        };
        let a = jet_at(&held.piece, held.piece.length());
        let b = jet_at(&next.piece, 0.0);
        let joined = norm(sub(a.d1, b.d1)) <= JOINT_D1_EPS && norm(sub(a.d2, b.d2)) <= JOINT_D2_EPS;
        if joined {
            self.piece(held.piece, &held.marks, held.last.feed, false, held.own, m, out);
            self.held = Some(next);
            return;
        }
        match transition(&mut held, &mut next, m) {
            Some((d_held, d_next, h, limits)) => {
                held.piece.u1 -= d_held;
                next.piece.u0 += d_next;
                let own = held.own.take();
                self.piece(held.piece, &held.marks, held.last.feed, false, own, m, out);
                let feed = held.last.feed.min(next.first.feed);
                let symmetric = matches!(
                    (held.piece.curve, next.piece.curve),
                    (Curve::Line(_), Curve::Line(_))
                );
                let (a, b, tol) = (&held.last.source, &next.first.source, held.last.tolerance);
                let marks = [(source_map::switch(&h, a, b, tol, symmetric), next.first.line)];
                let piece = Piece::whole(Curve::Hermite(h), held.last.line);
                self.piece(piece, &marks, feed, false, Some(limits), m, out);
                self.held = Some(next);
            }
            None => {
                let own = held.own.take();
                self.piece(held.piece, &held.marks, held.last.feed, true, own, m, out);
                self.held = Some(next);
            }
        }
    }

    fn flush_held(&mut self, m: &Machine, out: &mut Vec<PathBlock>) {
        if let Some(held) = self.held.take() {
            self.piece(held.piece, &held.marks, held.last.feed, true, held.own, m, out);
        }
        self.close_chain(0.0, m, out);
    }

    /// Stage 3: add a piece to the chain (`marks`: where source lines begin on it); `stop` after
    /// it. `known`: the piece's own limits if already computed (`piece_limits`).
    #[allow(clippy::too_many_arguments)]
    fn piece(
        &mut self,
        piece: Piece,
        marks: &[(f64, u32)],
        feed: f64,
        stop: bool,
        known: Option<CurveLimits>,
        m: &Machine,
        out: &mut Vec<PathBlock>,
    ) {
        if piece.length() > MIN_LENGTH {
            let mut cells = Vec::with_capacity(BOUND_PIECES);
            piece.curve.cells(|c| cells.push(c));
            let straight = matches!(piece.curve, Curve::Line(_));
            let sigma = piece.curve.speed_bound().max(1.0);
            // The speed class is the piece's own v_max; its ramps are within its own limits.
            let own = if straight {
                None
            } else {
                Some(known.unwrap_or_else(|| piece_limits(&cells, feed / sigma, m)))
            };
            let (class, ramps) = match &own {
                Some(l) => (l.class, (l.limits, l.bands.clone())),
                None => {
                    let Curve::Line(line) = piece.curve else {
                        unreachable!("straight pieces are lines")
                    };
                    let class = super::constant_speed_limit(&max_bounds(&cells), m).min(feed / sigma);
                    (class, (line_limits(line.direction(), m), Bands::default()))
                }
            };
            let fast = match &self.chain_ramps {
                Some(chain) if class <= self.chain_class => chain,
                _ => &ramps,
            };
            let joined = if !self.chain.is_empty()
                && feed == self.chain_feed
                && straight == self.chain_straight
                && self.chain.pieces.len() < CHAIN_MAX_PIECES
            {
                joined_loss(
                    self.chain_loss,
                    (self.chain.length(), self.chain_class),
                    (piece.length(), class),
                    fast,
                )
            } else {
                None
            };
            if let Some(loss) = joined {
                self.chain_loss = loss;
                self.chain_single = None;
            } else {
                self.chain_ramps = Some(ramps);
                self.close_chain(f64::INFINITY, m, out);
                self.chain_feed = feed;
                self.chain_class = class;
                self.chain_loss = 0.0;
                self.chain_straight = straight;
                self.cells.clear();
                self.chain_sigma = 1.0;
                self.chain_single = own;
            }
            self.chain_sigma = self.chain_sigma.max(sigma);
            self.chain_class = self.chain_class.min(class);
            self.cells.extend(cells);
            self.chain.push_marked(piece, marks);
        }
        if stop {
            self.close_chain(0.0, m, out);
        }
    }

    fn close_chain(&mut self, v_end_max: f64, m: &Machine, out: &mut Vec<PathBlock>) {
        if self.chain.is_empty() {
            return;
        }
        let chain = std::mem::take(&mut self.chain);
        let first = chain.pieces[0];
        let (segment, limits, bands, sigma) = match (chain.pieces.len(), first.curve) {
            (1, Curve::Line(_)) => {
                let line = Line {
                    start: first.start(),
                    end: first.end(),
                };
                let limits = line_limits(line.direction(), m);
                (Segment::Line(line), limits, Bands::default(), 1.0)
            }
            _ => {
                let v_cap = self.chain_feed / self.chain_sigma;
                let own = match self.chain_single.take() {
                    Some(l) if chain.pieces.len() == 1 => l,
                    _ => piece_limits(&self.cells, v_cap, m),
                };
                (Segment::Chain(chain), own.limits, own.bands, self.chain_sigma)
            }
        };
        out.push(PathBlock {
            line: first.line,
            segment,
            v_feed: (self.chain_feed / sigma).max(0.0).min(limits.v_max),
            limits,
            // A C2 joint limits nothing beyond the chain's own v_max (kept finite: the state
            // is serialised).
            v_end_max: v_end_max.min(limits.v_max),
            constant_speed: false,
            before_transition: false,
            bands,
        });
    }
}

impl Default for SmoothBuilder {
    fn default() -> Self {
        SmoothBuilder::new()
    }
}

pub(super) fn jet_at(piece: &Piece, u: f64) -> Jet {
    let g = piece.eval(u);
    Jet {
        p: if u >= piece.length() { piece.end() } else { g.p },
        d1: g.d1,
        d2: g.d2,
    }
}

/// Whether a piece of `length` and speed class `class` should join the chain (of `chain_length`
/// at `chain_class`, whose pieces already lose `chain_loss` to it) rather than start the next
/// one, by the time each way costs; the chain's loss if it joins. Joined, the faster side runs
/// at the slower one's speed v_slow over its length L. Apart, it is a block entered and left at
/// v_slow, reaching what it can of its own speed within its length (planned, within the faster
/// side's limits and bands `fast`): that saves L/v_slow − T_block. Their junction is then a
/// block end, where the acceleration is zero: a ramp from rest to the block's peak through it
/// takes T(0, v_slow) + T(v_slow, v_peak) rather than T(0, v_peak). Joining pays when what the
/// pieces lose to it, added up over the chain, stays within that. Decided on their times, the
/// two ways cost about the same where the choice changes with a limit.
pub(super) fn joined_loss(
    chain_loss: f64,
    (chain_length, chain_class): (f64, f64),
    (length, class): (f64, f64),
    fast: &(Limits, Bands),
) -> Option<f64> {
    let (v_slow, v_fast) = (chain_class.min(class), chain_class.max(class));
    if v_fast <= v_slow {
        return Some(chain_loss);
    }
    if v_slow <= 0.0 {
        return None;
    }
    let l_fast = if class < chain_class { chain_length } else { length };
    let banded = Banded {
        kind: ProfileKind::Scurve7,
        top: &fast.0,
        bands: &fast.1,
    };
    let (duration, v_peak) = scurve7_banded::plan_time(&banded, l_fast, v_slow, v_slow, v_fast);
    let loss = chain_loss + (l_fast / v_slow - duration).max(0.0);
    let from_rest = scurve7_banded::Rise::from(&banded, 0.0);
    let t = |v: f64| from_rest.time_distance(v).0;
    let apart = t(v_slow) + scurve7_banded::ramp_time(&banded, v_slow, v_peak) - t(v_peak);
    (loss <= apart).then_some(loss)
}

/// The vertex between two moves is smooth: two short line moves of one feed that turn gently,
/// whatever their lengths (CAM output alternates 8 µm and 1 µm moves; the fit checks every chord).
fn smooth_vertex(prev: &Move, next: &Move) -> bool {
    let (Source::Line(a), Source::Line(b)) = (prev.source, next.source) else {
        return false;
    };
    let (la, lb) = (a.length(), b.length());
    let cos = dot(a.direction(), b.direction());
    !(prev.exact
        || next.exact
        || prev.feed != next.feed
        || la > SMOOTH_MAX_SEGMENT
        || lb > SMOOTH_MAX_SEGMENT
        || cos < SMOOTH_MIN_COS)
}

fn start_of(mv: &Move) -> Vec3 {
    match mv.source {
        Source::Line(l) => l.start,
        Source::Arc(a) => a.start,
    }
}

fn end_of(mv: &Move) -> Vec3 {
    match mv.source {
        Source::Line(l) => l.end,
        Source::Arc(a) => a.end,
    }
}

/// Knot indices into the run's vertices (0 … moves): about `KNOT_LENGTH` apart in length.
fn choose_knots(run: &[Move]) -> Vec<usize> {
    let total: f64 = run.iter().map(|mv| mv.source.length()).sum();
    let spans = ((total / KNOT_LENGTH).round() as usize).clamp(1, run.len());
    let mut knots = vec![0];
    let mut acc = 0.0;
    for (i, mv) in run.iter().enumerate() {
        acc += mv.source.length();
        let next_target = total * knots.len() as f64 / spans as f64;
        if i + 1 < run.len() && acc >= next_target * (1.0 - KNOT_SLACK) {
            knots.push(i + 1);
        }
    }
    knots.push(run.len());
    knots
}

//! The `smooth` corner mode: every junction blended inside the path tolerance, runs of short
//! segments smoothed as one curve, and the result grouped into chains that one feed profile runs.
//!
//! Three streaming stages, each holding back at most one item:
//! 1. Vertices → spans (fit.rs). A vertex between two short G1 lines that turn gently is
//!    *smooth*; a run of such moves is fitted with quintic Hermite spans between knots, each
//!    kept only if it lies within the tolerance of its programmed chords, else split down to the
//!    programmed line.
//! 2. Junctions (junction.rs). Where two spans do not already join with equal first and second
//!    derivatives, both are cut back by d and a quintic Hermite transition (hermite.rs; eq.
//!    45–52 for two lines) joins them: d from the apex distance at the tolerance, at most half
//!    of the programmed line at each end, shrunk until the transition keeps the tolerance (closed
//!    form between lines, else sampled with a guaranteed guard), a stop where that is faster.
//!    Only G61, a reversal beyond `REVERSAL_COS` and the program's stops stop the path. A span's
//!    junction waits for the span after it: the transition at its far end, or a stop, bounds how
//!    fast it may leave the corner before.
//! 3. Chains. Consecutive pieces of similar speed class join one chain (chain.rs), whose limits
//!    bound its pieces' derivatives (`curve_limits`): every axis keeps its limits at any speed.

mod joined;

pub(super) use joined::{joined_loss, TIGHTER_RAMP};

use super::chain::{piece_limits, Chain, Curve, CurveLimits, Piece};
use super::fit::VertexJet;
use super::hermite::Jet;
use super::junction::{corner_ceiling, transition};
use super::micro::Tiny;
use super::source_map;
use super::tolerance::{JOINT_D1_EPS, JOINT_D2_EPS, MIN_LENGTH};
use super::{line_limits, max_bounds, PathBlock, Segment};
use crate::config::Machine;
use crate::feed::bands::Bands;
use crate::feed::Limits;
use crate::geometry::{dot, norm, sub, Line, Source};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Largest turning angle at a smooth vertex (cos), and longest segment smoothed.
const SMOOTH_MIN_COS: f64 = 0.866_025_403_784_438_6; // 30°
const SMOOTH_MAX_SEGMENT: f64 = 5e-3;
/// Moves held at most in one run before its spans are fitted.
const RUN_MAX: usize = 1024;
/// Pieces at most in one chain.
const CHAIN_MAX_PIECES: usize = 512;
/// A piece whose end is bound below this share of its own speed (by the transition after it,
/// toward a sharp corner) ramps nearly to rest within it, and joins a chain as one before a stop
/// does (`joined_loss`): a 0.23 mm arc ending at 0.71 mm/s joined a transition whose top band
/// left 148 mm/s² instead of 238, and ended 0.6 ms later.
const NEARLY_STOPS: f64 = 0.1;

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
    /// Length of the tiny moves this line took (micro.rs); 0 as programmed.
    pub absorbed: f64,
}

/// A span on its way through stage 2: the piece left of it, the programmed moves it stands for
/// and where the moves after the first begin on it (source_map.rs).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(super) struct Span {
    pub(super) piece: Piece,
    pub(super) first: Move,
    pub(super) last: Move,
    pub(super) marks: Vec<(f64, u32)>,
    /// The programmed moves, in order: the curve's parameter u runs along them as along their
    /// lengths (a transition checks its cut against those it replaces).
    pub(super) moves: Vec<Move>,
    /// The curve's own limits once computed (junction.rs needs them before stage 3 does; a
    /// cache, recomputed after a restore).
    #[serde(skip)]
    pub(super) own: Option<CurveLimits>,
    /// Bound on its speed where it begins: 0 after a stop (or at the start), the top speed of
    /// the transition before it, None where it joins its predecessor (junction.rs bounds its
    /// speed at the corner after it by what it can reach from there).
    pub(super) entry: Option<f64>,
    /// Its speed where it ends, once the span after it is known (set for its junction): 0 where
    /// a stop follows it, else the ceiling of the transition to that span as its search starts
    /// (junction.rs `corner_ceiling`: an estimate, the search may take a faster shorter cut);
    /// None where it joins that span with equal derivatives.
    #[serde(skip)]
    pub(super) exit: Option<f64>,
}

impl Span {
    pub(super) fn single(curve: Curve, mv: Move) -> Span {
        Span {
            piece: Piece::whole(curve, mv.line),
            first: mv,
            last: mv,
            marks: Vec::new(),
            moves: vec![mv],
            own: None,
            entry: Some(0.0),
            exit: None,
        }
    }

    /// The move `mv` as programmed, a line or an arc.
    pub(super) fn programmed(mv: Move) -> Span {
        let curve = match mv.source {
            Source::Arc(a) => Curve::Arc(a),
            Source::Line(l) => Curve::Line(l),
        };
        Span::single(curve, mv)
    }

    /// The line of `moves`, which continue one line.
    pub(super) fn line(moves: &[Move]) -> Span {
        let (first, last) = (moves[0], moves[moves.len() - 1]);
        let line = Line {
            start: start_of(&first),
            end: end_of(&last),
        };
        Span::fitted(Piece::whole(Curve::Line(line), first.line), moves)
    }

    /// `piece` standing for `moves` (u along it as along the moves).
    pub(super) fn fitted(piece: Piece, moves: &[Move]) -> Span {
        Span {
            piece,
            first: moves[0],
            last: moves[moves.len() - 1],
            marks: source_map::span_marks(moves),
            moves: moves.to_vec(),
            own: None,
            entry: Some(0.0),
            exit: None,
        }
    }

    /// The moves the last `d` of its piece stands for, in order.
    pub(super) fn moves_at_end(&self, d: f64) -> &[Move] {
        let from = self.piece.u1 - d;
        let mut start = 0.0;
        let k = self.moves.iter().position(|mv| {
            start += mv.source.length();
            start > from
        });
        &self.moves[k.unwrap_or(self.moves.len() - 1)..]
    }

    /// The moves the first `d` of its piece stands for, in order.
    pub(super) fn moves_at_start(&self, d: f64) -> &[Move] {
        let to = self.piece.u0 + d;
        let (mut start, mut first, mut end) = (0.0, None, self.moves.len());
        for (k, mv) in self.moves.iter().enumerate() {
            let next = start + mv.source.length();
            if next > self.piece.u0 && first.is_none() {
                first = Some(k);
            }
            if start >= to && first.is_some() {
                end = k;
                break;
            }
            start = next;
        }
        let first = first.unwrap_or(self.moves.len() - 1);
        &self.moves[first..end.max(first + 1)]
    }
}

/// Whether `after` continues `span` with equal first and second derivatives (no transition).
pub(super) fn joined(span: &Span, after: &Span) -> bool {
    let a = jet_at(&span.piece, span.piece.length());
    let b = jet_at(&after.piece, 0.0);
    norm(sub(a.d1, b.d1)) <= JOINT_D1_EPS && norm(sub(a.d2, b.d2)) <= JOINT_D2_EPS
}

/// The programmed geometry of `moves` (one move, or moves that continue one line) as one.
pub(super) fn programmed(moves: &[Move]) -> Source {
    match moves {
        [one] => one.source,
        _ => Source::Line(Line {
            start: start_of(&moves[0]),
            end: end_of(&moves[moves.len() - 1]),
        }),
    }
}

/// The smooth-mode builder (see the module comment).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SmoothBuilder {
    /// Stage 1: the run of moves whose inner vertices are smooth, and the jet at its first vertex
    /// (None: a corner, or the start).
    pub(super) run: Vec<Move>,
    pub(super) run_jet: VertexJet,
    /// Stage 2: the span waiting for its junction with the next.
    pub(super) held: Option<Span>,
    /// Stage 3: the chain being filled, its pieces' bound cells (all, or none: `Chain::cells`),
    /// feed and speed class.
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
    /// Whether the chain starts from rest (`joined_loss`), and whether the last chain closed did
    /// end at rest (the next one then starts from it).
    #[serde(default)]
    chain_from_rest: bool,
    #[serde(default)]
    ended_at_rest: bool,
    /// The last span stage 1 gave, waiting for the next one or a stop (its exit) before its
    /// junction with the held span.
    pub(super) waiting: Option<Span>,
}

impl SmoothBuilder {
    /// A restored builder: its moves, held span and chain checked (the chain may be empty).
    pub fn check_state(&self) -> Result<(), String> {
        use super::check::{one_piece, pieces, programmed};
        self.run.iter().try_for_each(programmed)?;
        for s in self.held.iter().chain(&self.waiting) {
            one_piece(&s.piece)?;
            [s.first, s.last]
                .iter()
                .chain(&s.moves)
                .try_for_each(programmed)?;
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
            chain_from_rest: true,
            ended_at_rest: true,
            waiting: None,
        }
    }

    /// Take one programmed move.
    pub fn push(&mut self, mv: Move, m: &Machine, out: &mut Vec<PathBlock>) {
        if let Some(last) = self.run.last().copied() {
            if smooth_vertex(&last, &mv) {
                if self.run.len() >= RUN_MAX {
                    self.flush_run(true, None, m, out);
                }
            } else if last.exact || mv.exact {
                self.stop(m, out);
            } else {
                self.flush_run(false, Some(&mv), m, out);
            }
        }
        self.run.push(mv);
    }

    /// The last move received ends where `tiny` moves after it end, if it is a line not yet
    /// run that they start at and may join (micro.rs): its end moves by at most their length,
    /// and so does each of its points, so its tolerance is lowered by that; its vertex with the
    /// move before stays as smooth as it was. Whether it did.
    pub(super) fn end_last_at(&mut self, tiny: &Tiny) -> bool {
        let n = self.run.len();
        let Some(last) = self.run.last() else { return false };
        let Source::Line(line) = last.source else {
            return false;
        };
        if last.exact || line.end != tiny.start || !tiny.fits(last.tolerance) {
            return false;
        }
        let moved = tiny.ending(last, line.start);
        if n >= 2 && smooth_vertex(&self.run[n - 2], last) != smooth_vertex(&self.run[n - 2], &moved) {
            return false;
        }
        self.run[n - 1] = moved;
        true
    }

    /// Stop at the end of everything received (dwell, M0, program end, an exact-stop move):
    /// the waiting span ends at rest.
    pub fn stop(&mut self, m: &Machine, out: &mut Vec<PathBlock>) {
        self.flush_run(false, None, m, out);
        if let Some(mut last) = self.waiting.take() {
            last.exit = Some(0.0);
            self.join(last, m, out);
        }
        self.flush_held(m, out);
    }

    /// Whether the next span stage 1 gives starts at rest: nothing has come since a stop.
    pub(super) fn at_rest(&self) -> bool {
        self.held.is_none() && self.waiting.is_none()
    }

    /// Stage 2 for the span stage 1 gives: it waits, and the span that waited is joined to the
    /// held span, knowing its exit.
    pub(super) fn junction(&mut self, next: Span, m: &Machine, out: &mut Vec<PathBlock>) {
        let Some(mut span) = self.waiting.replace(next) else {
            return;
        };
        if let Some(after) = &self.waiting {
            // Where `span` starts at a corner, its transition may take up to half of it.
            let shared = self.held.as_ref().is_some_and(|held| !joined(held, &span));
            span.exit = (!joined(&span, after)).then(|| corner_ceiling(&span, after, shared, m));
        }
        self.join(span, m, out);
    }

    /// Stage 2: join `next` to the held span.
    fn join(&mut self, mut next: Span, m: &Machine, out: &mut Vec<PathBlock>) {
        let Some(mut held) = self.held.take() else {
            self.held = Some(next);
            return;
        };
        if joined(&held, &next) {
            let (feed, own) = (held.last.feed, held.own);
            self.piece(held.piece, &held.marks, feed, f64::INFINITY, own, m, out);
            next.entry = None;
            self.held = Some(next);
            return;
        }
        match transition(&mut held, &mut next, m) {
            Some((d_held, d_next, h, limits, leads)) => {
                let symmetric = matches!(
                    (held.piece.curve, next.piece.curve),
                    (Curve::Line(_), Curve::Line(_))
                );
                let (before, after) = (held.moves_at_end(d_held), next.moves_at_start(d_next));
                let (line, marks) = source_map::transition_marks(&h, before, after, symmetric, &leads);
                held.piece.u1 -= d_held;
                next.piece.u0 += d_next;
                let own = held.own.take();
                self.piece(held.piece, &held.marks, held.last.feed, limits.class, own, m, out);
                let feed = held.last.feed.min(next.first.feed);
                next.entry = Some(limits.class);
                let piece = Piece::whole(Curve::Hermite(h), line);
                self.piece(piece, &marks, feed, f64::INFINITY, Some(limits), m, out);
                self.held = Some(next);
            }
            None => {
                let own = held.own.take();
                self.piece(held.piece, &held.marks, held.last.feed, 0.0, own, m, out);
                self.held = Some(next);
            }
        }
    }

    fn flush_held(&mut self, m: &Machine, out: &mut Vec<PathBlock>) {
        if let Some(held) = self.held.take() {
            self.piece(held.piece, &held.marks, held.last.feed, 0.0, held.own, m, out);
        }
        self.close_chain(0.0, m, out);
    }

    /// Stage 3: add a piece to the chain (`marks`: where source lines begin on it); `end`: the
    /// bound on its end speed (0 at a stop, the class of the transition after it, or infinite
    /// where it runs on). `known`: the piece's own limits if already computed (`piece_limits`).
    #[allow(clippy::too_many_arguments)]
    fn piece(
        &mut self,
        piece: Piece,
        marks: &[(f64, u32)],
        feed: f64,
        end: f64,
        known: Option<CurveLimits>,
        m: &Machine,
        out: &mut Vec<PathBlock>,
    ) {
        if piece.length() > MIN_LENGTH {
            let straight = matches!(piece.curve, Curve::Line(_));
            // Its cells where its class needs them: the chain holds all its pieces' or none, and
            // then takes them as it closes (`Chain::cells`).
            let mut cells = Vec::new();
            if straight || known.is_none() {
                piece.curve.cells(|c| cells.push(c));
            }
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
            let (fast, slow) = match &self.chain_ramps {
                Some(chain) if class <= self.chain_class => (chain, &ramps),
                Some(chain) => (&ramps, chain),
                None => (&ramps, &ramps),
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
                    (&fast.0, &fast.1),
                    (&slow.0, &slow.1),
                    (self.chain_from_rest, end <= NEARLY_STOPS * class),
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
                self.chain_from_rest = std::mem::take(&mut self.ended_at_rest);
            }
            self.chain_sigma = self.chain_sigma.max(sigma);
            self.chain_class = self.chain_class.min(class);
            if cells.is_empty() || !self.chain.is_empty() && self.cells.is_empty() {
                self.cells.clear();
            } else {
                self.cells.extend(cells);
            }
            self.chain.push_marked(piece, marks);
        }
        if end == 0.0 {
            self.close_chain(0.0, m, out);
        }
    }

    fn close_chain(&mut self, v_end_max: f64, m: &Machine, out: &mut Vec<PathBlock>) {
        self.ended_at_rest |= v_end_max == 0.0;
        if self.chain.is_empty() {
            return;
        }
        let chain = std::mem::take(&mut self.chain);
        let (first, line) = (&chain.pieces[0], chain.line_at(0.0));
        let (segment, limits, bands, sigma) = match (chain.pieces.len(), &first.curve) {
            // A plain line block reports one program line (a line of several moves stays a chain).
            (1, Curve::Line(_)) if chain.one_source() => {
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
                    _ => piece_limits(chain.cells(&mut self.cells), v_cap, m),
                };
                (Segment::Chain(chain), own.limits, own.bands, self.chain_sigma)
            }
        };
        out.push(PathBlock {
            line,
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

pub(super) fn start_of(mv: &Move) -> Vec3 {
    match mv.source {
        Source::Line(l) => l.start,
        Source::Arc(a) => a.start,
    }
}

pub(super) fn end_of(mv: &Move) -> Vec3 {
    match mv.source {
        Source::Line(l) => l.end,
        Source::Arc(a) => a.end,
    }
}

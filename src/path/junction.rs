//! Stage 2 of the `smooth` corner mode (smooth.rs): the transition at a junction of two pieces
//! that do not meet with equal first and second derivatives — a quintic Hermite (hermite.rs;
//! eq. 45–52 between two lines) from a cut d on each side, d from eq. 52's apex at the tolerance,
//! shrunk along a grid of cuts until the transition keeps the tolerance, then halved while that
//! costs less time at the corner (`local_cost`, junction/cost.rs) and refined about the best, or
//! None (a stop at the corner, where that costs less). The tolerance only admits cuts (the grid
//! hangs from the geometry); the time picks among them, so a larger tolerance seldom picks a
//! slower one.

mod cost;
mod crossing;
mod estimate;
mod tie;

pub(super) use estimate::{corner_ceiling, corner_speed, end_reach};

use super::chain::{Curve, CurveLimits, Own};
use super::cover::{lead, Guards, Leads, UNMEASURED};
use super::hermite::{Hermite, Unbounded};
use super::slowest_axis;
use super::smooth::{jet_at, Move, Span};
use super::tolerance::{MIN_LENGTH, REVERSAL_COS, TRANSITION_SAMPLES};
use crate::config::Machine;
use crate::feed::scurve7_banded::Rise;
use crate::feed::{scurve7, BlockRequest, FeedLaw};
use crate::geometry::{dot, norm, sub, unit};
use cost::{cost_floor, entry_drop, joined_sides, local_cost, side, stop_below, End, Far, Side};

/// Steps down the grid of cuts (`GRID`) before the junction stops instead.
const MAX_SHRINKS: usize = 60;

/// The limits of transition `h` at `feed` if running through it beats stopping at the corner:
/// its time at its speed limit is at most the rest-to-rest time over its length within the feed
/// and the axes' acceleration and jerk (a stop costs at least that; the neighbours' ramps come on
/// top). A tiny sharp transition allows so little speed that stopping is quicker; a long gentle
/// one (lines meeting at a rounding kink) runs at the feed.
fn faster_than_a_stop(h: &Hermite, feed: f64, m: &Machine) -> Option<(f64, Own)> {
    let mut own = Own::of(h, feed, m);
    let t_stop = scurve7::plan(&BlockRequest {
        length: h.length(),
        v_in: 0.0,
        v_out: 0.0,
        v_feed: feed,
        limits: slowest_axis(m, feed),
    })
    .duration();
    let v_max = own.speed(m);
    (h.length() <= v_max * t_stop).then_some((v_max, own))
}

/// The corner between `held` and `next`: how much it turns, |t_out − t_in|, and its reach, the
/// longest cut: all that is left of the span before (the transition at its start has cut it
/// already) and half of the span after (the other half for the corner at its end), over as
/// many programmed moves as they stand for. None at a reversal.
fn corner(held: &Span, next: &Span) -> Option<(f64, f64)> {
    let end = jet_at(&held.piece, held.piece.length());
    let start = jet_at(&next.piece, 0.0);
    let (t_in, t_out) = (unit(end.d1), unit(start.d1));
    if dot(t_in, t_out) < REVERSAL_COS {
        return None;
    }
    let reach = held.piece.length().min(0.5 * next.piece.length());
    Some((norm(sub(t_out, t_in)), reach))
}

/// The transition for cut `d` on both sides of the corner between `held` and `next`, with
/// parameter speed 1 at both ends: λ is 2·share times the cut (before its speed bound).
fn cut_shape(held: &Span, next: &Span, d: f64, share: f64) -> Unbounded {
    let a = jet_at(&held.piece, held.piece.length() - d);
    let b = jet_at(&next.piece, d);
    Hermite::unbounded(a, b, 2.0 * share * d)
}

/// The transition between `held` and `next`: the cuts on both sides, the curve, its limits and
/// its samples' `Leads`, or None (stop) at a reversal or when no cut keeps the tolerance.
pub(super) fn transition(
    held: &mut Span,
    next: &mut Span,
    m: &Machine,
) -> Option<(f64, f64, Hermite, CurveLimits, Leads)> {
    let (w, reach) = corner(held, next)?;
    let tol = held.last.tolerance;
    // Two lines: the largest deviation is at the apex, in closed form (`apex_share`).
    let lines = matches!(
        (held.piece.curve, next.piece.curve),
        (Curve::Line(_), Curve::Line(_))
    );
    let feed = held.last.feed.min(next.first.feed);
    let mut sides = [side(held, held.last.feed, m), side(next, next.first.feed, m)];
    // The span before rises from its entry speed, the span after drops to its exit speed where
    // known (a drop takes what the rise takes), each within its own limits (copied: the sides
    // change below). Neither runs faster at the corner than that reaches over its length.
    let lengths = [held.piece.length(), next.piece.length()];
    let known = [held.entry, next.exit];
    let ends: [Option<End>; 2] = std::array::from_fn(|k| {
        let side = &sides[k];
        known[k].filter(|&v| v < side.v).map(|v| End {
            v: v.max(0.0),
            top: side.top,
            bands: side.bands.clone(),
        })
    });
    let banded = ends.each_ref().map(|e| e.as_ref().map(End::banded));
    // Each rise is a few kB: built where it stays, not moved through an array.
    let mut slots = [None, None];
    let [before, after] = &mut slots;
    let rises = [(before, 0), (after, 1)].map(|(slot, k)| match (&banded[k], &ends[k]) {
        (Some(b), Some(end)) => Some(Rise::build_in(slot, b, end.v)),
        _ => None,
    });
    for (side, (rise, length)) in sides.iter_mut().zip(rises.into_iter().zip(lengths)) {
        if let Some(rise) = rise {
            side.v = side.v.min(rise.max_speed(length));
        }
    }
    joined_sides(&mut sides);
    // The span before starts at rest after a stop (its entry is a bound otherwise), the span
    // after ends at its exit (a stop, or the estimate at its far corner): the block between the
    // corner and there (`local_cost`). The cuts are compared with the span after's block to a
    // stop alone (as run; the estimate's would move every corner's choice for little).
    let far = [held.entry.filter(|&v| v == 0.0), next.exit];
    let far_of = |k: usize, side: &Side| {
        far[k].map(|v| Far {
            v,
            at_start: k == 0,
            ramp: match rises[k] {
                Some(rise) if v < side.beside(v) => rise.time_distance(side.beside(v)),
                _ => (0.0, 0.0),
            },
        })
    };
    sides[1].far = far_of(1, &sides[1]).filter(|f| f.v == 0.0);
    let slower = sides[0].v.min(sides[1].v);
    let search = Search {
        held,
        next,
        reach,
        sides: &sides,
        // With the distance each takes to the slower side's speed: a cut that leaves less of
        // its span meets the transition slower than that.
        ends: rises.map(|r| r.map(|rise| (rise, rise.time_distance(slower).1))),
        feed,
        lines,
        m,
    };
    // The best cut so far, `cuts[at]`, and the slot the next share's search writes into: they
    // swap roles where that one is cheaper (a cut is not copied between them).
    let mut cuts: [Option<Found>; 2] = [None, None];
    let (mut at, mut longest) = (0, f64::INFINITY);
    for (k, &share) in LAMBDA_SHARES.iter().enumerate() {
        let best = &cuts[at];
        // A transition at the feed or at its slower neighbour's speed keeps λ = 2d: a shorter
        // one runs no faster there. The time falls with the share down to its best, then rises:
        // a share that did not improve ends the search. Between curves, each try costs the
        // sampled tolerance check: only tight corners try.
        let limit = (feed / 1f64.max(best.as_ref().map_or(1.0, |b| b.h.speed_bound())))
            .min(sides[0].v)
            .min(sides[1].v);
        let tries = if lines { AT_FEED } else { TIGHT };
        if best
            .as_ref()
            .is_some_and(|b| b.v >= tries * limit || b.share != LAMBDA_SHARES[k - 1])
        {
            break;
        }
        // A shorter λ deviates more at the same cut: its longest admissible cut is no longer than
        // the last share's, where the search starts (fewer tolerance checks).
        let start = apex_cut(tol, w, share).min(reach).min(longest);
        // A shorter λ changes the curve at a cut: where at the best cut's own length (or its
        // longest admitted, if shorter) it does not cost less even at its speed's ceiling, its
        // search is not run. The CAM-like 10 k lines ran 1552 such searches, 47 of which found a
        // cheaper cut (1.7 ms of their 293.8 s in all); none runs now. The corners of LinuxCNC's
        // zigzag tests, where a shorter λ gains up to 8 %, run as before.
        if best
            .as_ref()
            .is_some_and(|b| !search.may_beat(b, b.d.min(start), share))
        {
            break;
        }
        if let Some(admitted) = search.cuts(start, share, &mut cuts[1 - at]) {
            longest = admitted;
            let best = &cuts[at];
            if cuts[1 - at]
                .as_ref()
                .is_some_and(|found| best.as_ref().is_none_or(|b| found.cost < b.cost - SAVING))
            {
                at = 1 - at;
            }
        }
    }
    // A stop is the shortest cut of all (every tolerance admits it): taken where it costs less,
    // with the spans beside the corner running on at their own speeds and with their far ends
    // counted too (a short span's ramps to and from the corner share its length: where the
    // first says stop, the second often does not).
    let best = cuts[at].as_ref()?;
    // Each side of the comparison is charged what the corner before loses to it
    // (`entry_drop`), solved only where the stop may win without that.
    let drops = stop_below(&sides, best.cost - SAVING).then(|| {
        let stop_drop = entry_drop(search.held, &sides[0], 0.0, 0.0);
        (stop_drop, entry_drop(search.held, &sides[0], best.d, best.at))
    });
    let drops = drops.filter(|&(stop_drop, _)| stop_below(&sides, best.cost - SAVING - stop_drop));
    if let Some((stop_drop, best_drop)) = drops {
        for (k, side) in sides.iter_mut().enumerate() {
            side.far = far_of(k, side);
        }
        let at_best = local_cost(best.d, best.h.length(), best.at, &sides);
        if stop_below(&sides, at_best + best_drop - SAVING - stop_drop) {
            return None;
        }
    }
    let limits = best.own.limits(m);
    Some((best.d, best.d, best.h, limits, best.leads))
}

/// A transition's speed at this share of the feed (or of its slower neighbour's speed) or above
/// counts as at the feed; a corner between curves whose transition runs below `TIGHT` of it is
/// tight (where a shorter λ gains: on the CAM-like program 94 % of the time it saves, for a
/// fifth of the search's CPU).
const AT_FEED: f64 = 0.95;
const TIGHT: f64 = 0.25;

/// A cut found: its time at the corner, the cut, the curve, its cells and its top speed.
struct Found {
    cost: f64,
    /// The speed it was costed at.
    at: f64,
    d: f64,
    h: Hermite,
    own: Own,
    v: f64,
    share: f64,
    /// Its index on the junction's grid of cuts.
    k: i32,
    /// Its samples' distances from the tolerance check (set once it is checked).
    leads: Leads,
}

/// Shares of 2d tried as the transition's parameter length λ (cut d on both sides, |p'| = 1 at
/// both ends). Seed 004 takes λ = 2d (eq. 51); a shorter λ makes the curvature more even along
/// the transition (between two lines meeting at 53°, its peak is 1.71 times the mean turning
/// rate at share 1, 1.22 at 0.8), which the speed limit of a tight corner gains by, while |p'|
/// rises in the middle (1.31 at share 0.8), which a corner run at the feed loses by. The time
/// at the corner picks among them.
const LAMBDA_SHARES: [f64; 3] = [1.0, 0.85, 0.7];

/// The apex of the transition between two lines with cut d and λ = 2·share·d lies
/// |t_out − t_in|·d·apex_share(share) from the corner: p(λ/2) = corner + (t_out − t_in)·(d/2 −
/// 5λ/32) (3/16 at share 1, eq. 52). For shares in [0.5, 1] the curve is convex and symmetric,
/// so its distance from either line grows towards the apex: the largest deviation is there.
pub(super) fn apex_share(share: f64) -> f64 {
    0.5 - 5.0 * share / 16.0
}

/// The cut whose apex lies at `tol` from a corner turning by w = |t_out − t_in| (eq. 52 at share
/// 1; `apex_share`): ∞ where the lines do not turn.
fn apex_cut(tol: f64, w: f64, share: f64) -> f64 {
    if w > 0.0 {
        tol / (w * apex_share(share))
    } else {
        f64::INFINITY
    }
}

/// What a junction's cut search needs: the two sides, the tolerance and the feed.
struct Search<'a> {
    held: &'a Span,
    next: &'a Span,
    /// The longest cut (the top of the grid of cuts).
    reach: f64,
    sides: &'a [Side; 2],
    /// The span before's rise from its entry speed and the span after's drop to its exit speed,
    /// where known and below their own, each with the distance it takes to the slower side's
    /// speed.
    ends: [Option<(&'a Rise<'a>, f64)>; 2],
    feed: f64,
    lines: bool,
    m: &'a Machine,
}

impl Search<'_> {
    /// The slower side's speed: a cut runs no faster.
    fn slower(&self) -> f64 {
        self.sides[0].v.min(self.sides[1].v)
    }

    /// The cut at index `k` (`first`: the grid index of the first grid cut at or below the
    /// start of the search, and that start; an index below it stands for the start itself) and
    /// its curve for λ = 2·share·d, if longer than `MIN_LENGTH`.
    fn at(&self, k: i32, first: (i32, f64), share: f64) -> Option<(f64, Hermite)> {
        self.shape_at(k, first, share)
            .map(|(d, shape)| (d, shape.bounded()))
    }

    /// `at` before the curve's speed bound.
    fn shape_at(&self, k: i32, first: (i32, f64), share: f64) -> Option<(f64, Unbounded)> {
        let d = if k < first.0 {
            first.1
        } else {
            self.reach * GRID.powi(k)
        };
        if d.is_nan() || d <= MIN_LENGTH {
            return None;
        }
        Some((d, cut_shape(self.held, self.next, d, share)))
    }

    /// Whether the curve `h` of cut `d` is within the tolerance, its samples' `Leads` written to
    /// `leads` (in place: a returned array was copied on each way out).
    fn within(&self, d: f64, h: &Hermite, leads: &mut Leads) -> bool {
        if self.lines {
            *leads = None;
            return true;
        }
        let (before, after) = (self.held.moves_at_end(d), self.next.moves_at_start(d));
        within_tolerance(h, before, after, leads.insert([0.0; TRANSITION_SAMPLES + 1]))
    }

    /// The speed cut `d` is costed at: its own top speed `v_max`, no faster than the slower
    /// neighbour (where the cut leaves nothing of the span before, the piece before it: no
    /// faster than that span's entry), than the span before reaches from its entry over what the
    /// cut leaves of it, nor than the span after slows from to its exit (rest at a stop, else the
    /// ceiling of the transition at its end) over what is left of it: the transition meets them
    /// there (a longer cut leaves less room). Each rise is solved only where it takes more than
    /// that rest to the speed so far. A cut that leaves nothing of a span that starts at rest
    /// starts at rest: speed 0, never taken over a shorter cut. At the speed's ceiling it bounds
    /// the cost from below (`try_at` prunes by it). `solved`: each end's top speed over what is
    /// left of its span, once solved for this cut (the same rise and rest, the same speed).
    fn speed(&self, d: f64, v_max: f64, solved: &mut [Option<f64>; 2]) -> f64 {
        let rests = [self.held.piece.length(), self.next.piece.length()].map(|l| (l - d).max(0.0));
        if rests[0] == 0.0 && self.held.entry == Some(0.0) {
            return 0.0;
        }
        let slower = self.slower();
        let mut v = v_max.min(slower);
        if rests[0] == 0.0 {
            v = v.min(self.held.entry.unwrap_or(v));
        }
        for ((end, rest), solved) in self.ends.iter().zip(rests).zip(solved) {
            if let Some((rise, _)) = end.filter(|&(_, to_slower)| rest < to_slower) {
                // At the slower side's speed the rise takes `to_slower`, more than `rest`.
                if v == slower || rise.time_distance(v).1 > rest {
                    v = v.min(*solved.get_or_insert_with(|| rise.max_speed(rest)));
                }
            }
        }
        v
    }

    /// Whether the curve for cut d and λ = 2·share·d may cost less than `best`: its cost at its
    /// speed's ceiling (a bound from below) is clearly less. Not at a cut no longer than
    /// `MIN_LENGTH`, which the search would not take either.
    fn may_beat(&self, best: &Found, d: f64, share: f64) -> bool {
        if d.is_nan() || d <= MIN_LENGTH {
            return false;
        }
        let h = cut_shape(self.held, self.next, d, share);
        let v_ceiling = self.speed(d, Own::ceiling_of(&h, self.feed, self.m), &mut [None; 2]);
        local_cost(d, h.length(), v_ceiling, self.sides) < best.cost - SAVING
    }

    /// Its time at the corner: faster than the slower neighbour, it runs at that one's speed
    /// (in its chain, or with no room to ramp between), so at the slowest of the three.
    /// `known`: a speed this cut was costed at already, and that cost; `solved` as for `speed`.
    #[allow(clippy::too_many_arguments)]
    fn found(
        &self,
        k: i32,
        d: f64,
        h: Hermite,
        (v_max, own): (f64, Own),
        share: f64,
        known: Option<(f64, f64)>,
        solved: &mut [Option<f64>; 2],
    ) -> Found {
        let v = self.speed(d, v_max, solved);
        Found {
            at: v,
            cost: match known {
                Some((at, cost)) if at == v => cost,
                _ => local_cost(d, h.length(), v, self.sides),
            },
            d,
            h,
            own,
            v: v_max,
            share,
            k,
            leads: None,
        }
    }

    /// The cut for λ = 2·share·d, from `start` and the grid's cuts below it: the longest within
    /// the tolerance that beats a stop, then the grid's shorter cuts by halves while they cost
    /// less (a longer transition is faster through the corner but replaces more of a faster
    /// neighbour), then a quarter and an eighth of the octave about the best. The grid hangs
    /// from the junction's reach, not from the tolerance: a larger tolerance admits every cut a
    /// smaller one did and compares them too. None: a stop costs less; else the longest cut
    /// admitted, the cut chosen in `slot` (in place: a returned cut was copied on each way out).
    fn cuts(&self, start: f64, share: f64, slot: &mut Option<Found>) -> Option<f64> {
        let m = self.m;
        // The first grid cut at or below `start` (the rounding of the log checked).
        let mut k = if start >= self.reach {
            0
        } else {
            ((start / self.reach).ln() / GRID.ln())
                .ceil()
                .min(MAX_GRID as f64) as i32
        };
        if self.reach * GRID.powi(k) > start {
            k += 1;
        }
        // The start first (the apex cut at the tolerance, or the reach), then the grid below it.
        let first = (k, start);
        if self.reach * GRID.powi(k) < start {
            k -= 1;
        }
        *slot = None;
        let mut stop_tries = 0;
        let mut leads = None;
        for _ in 0..MAX_SHRINKS {
            let (d, h) = self.at(k, first, share)?;
            if !self.within(d, &h, &mut leads) {
                k += 1;
                continue;
            }
            // A shorter cut may beat a stop where the longest does not (its time grows as √d, a
            // jerk-limited stop's as ∛d): a larger tolerance, which admits it too, must not stop
            // where a smaller one runs through.
            match faster_than_a_stop(&h, self.feed, m) {
                Some(speed) => {
                    let mut found = self.found(k, d, h, speed, share, None, &mut [None; 2]);
                    found.cost += entry_drop(self.held, &self.sides[0], d, found.at);
                    found.leads = leads;
                    *slot = Some(found);
                    break;
                }
                None if stop_tries == STOP_TRIES => return None,
                None => {
                    stop_tries += 1;
                    k += OCTAVE;
                }
            }
        }
        let best = slot.as_mut()?;
        let (admitted, longest) = (best.k, best.d);
        // The speed ceiling of the last cut tried.
        let last_ceiling = std::cell::Cell::new(f64::INFINITY);
        // The cut at index k, into `best`, if it is within the tolerance and cheaper than `best`
        // by `SAVING` (in place: a returned cut was copied on each way out).
        let try_cut = |k: i32, (d, shape): (f64, Unbounded), best: &mut Found| {
            // The curve's speed bound only where its frame needs it, or once the cut is not pruned.
            let mut own = Own::of_shape(&shape, self.feed, m);
            // The cost falls with the speed: where even the speed's ceiling costs clearly more
            // (`PRUNE_MARGIN`), the cut is not taken (most tries are not), unsolved.
            let mut solved = [None; 2];
            let v_ceiling = self.speed(d, own.ceiling(), &mut solved);
            last_ceiling.set(v_ceiling);
            let prune = best.cost + self.tie(best) + PRUNE_MARGIN * best.cost.abs();
            // Most of them are pruned by a bound of that cost from below (`cost_floor`), without
            // the banded ramps' solves.
            if cost_floor(d, shape.length(), v_ceiling, self.sides).is_some_and(|c| c >= prune) {
                return None;
            }
            let at_ceiling = local_cost(d, shape.length(), v_ceiling, self.sides);
            if at_ceiling >= prune {
                return None;
            }
            let h = shape.bounded_with(own.sigma());
            let v_max = own.speed(m);
            // Where the neighbours cap both speeds alike, the cost is the one just found.
            let known = Some((v_ceiling, at_ceiling));
            let mut shorter = self.found(k, d, h, (v_max, own), share, known, &mut solved);
            let cheaper = shorter.cost < best.cost - SAVING;
            (cheaper || shorter.ties_faster(best) && self.apart(&shorter)).then_some(())?;
            // Only raises the cost: solved only where the cut would be taken without it.
            shorter.cost += entry_drop(self.held, &self.sides[0], d, shorter.at);
            let still = shorter.cost < best.cost - SAVING;
            (still || shorter.ties_faster(best) && (!cheaper || self.apart(&shorter))).then_some(())?;
            self.within(d, &shorter.h, &mut shorter.leads).then_some(())?;
            *best = shorter;
            Some(())
        };
        let try_at = |k: i32, best: &mut Found| try_cut(k, self.shape_at(k, first, share)?, best);
        // Down by halves while cheaper. Where the best is held below its own top speed (to a
        // neighbour's) and the halving that was not cheaper is slower than that, the cost rose
        // with the curve's speed, not with what it replaces, and may fall again further down:
        // one more halving is tried.
        loop {
            while try_at(best.k + OCTAVE, best).is_some() {}
            let held = best.at < best.v && last_ceiling.get() < best.at;
            if !(held && try_at(best.k + 2 * OCTAVE, best).is_some()) {
                break;
            }
        }
        // Then a quarter and an eighth of the octave about the best.
        for step in [OCTAVE / 2, OCTAVE / 4] {
            let around = [best.k - step, best.k + step];
            for k in around.into_iter().filter(|&k| k >= admitted) {
                try_at(k, best);
            }
        }
        // Where the next longer cut is capped by the rise of the span before and the best is
        // not, the cost has its kink between them: the cut where the rise meets the curve's
        // speed, on the grid or off it, so a larger tolerance finds it where a smaller one's
        // first cut fell near it (seed 5 case 737: 0.0455 mm at 6.85 mm/s, the grid's 0.0408
        // at 6.37 and 0.0485 at 6.57). A best run below its own speed and its sides' is capped
        // already (past the kink).
        let uncapped = best.at >= best.v.min(self.slower());
        let longer = (uncapped && best.k > admitted && self.ends[0].is_some())
            .then(|| self.shape_at(best.k - 1, first, share));
        // The best's ceiling is its shape's (`Own::ceiling_of`): it came from `try_cut`, above
        // the admitted cut.
        let free = (best.d, best.own.ceiling());
        if let Some(cut) = longer
            .flatten()
            .and_then(|capped| self.rise_crossing(free, capped, share))
        {
            try_cut(best.k, cut, best);
        }
        Some(longest)
    }
}

/// Ratio between neighbouring cuts of a junction's grid (2^(-1/4): `OCTAVE` steps halve the
/// cut), and the grid's last index.
const GRID: f64 = 0.840_896_415_253_714_5;
const OCTAVE: i32 = 4;
const MAX_GRID: i32 = 400;

/// Least saving (s) for which a shorter cut is taken: far below a tick, far above rounding (equal
/// costs keep the longer cut, unless the shorter one gains this much more on its own:
/// `Found::ties_faster`).
const SAVING: f64 = 1e-6;
/// Share of the best cut's cost by which a shorter cut's cost at its speed's ceiling must exceed
/// it before the cut is dropped unsolved: far above the noise of the ramps' solves (`RAMP_FIT`),
/// which makes the cost fall with the speed only to within it.
const PRUNE_MARGIN: f64 = 1e-2;
/// Halvings of an admitted cut tried where a stop costs less than it, before the corner stops.
const STOP_TRIES: u32 = 4;

/// Every point of `h` within the tolerance of one of the programmed moves it replaces (`before`
/// and `after` the corner, in path order): each of its samples keeps the half-steps about it
/// within the tolerance of one (cover.rs). Its samples' distances (`Leads`) go to `leads`.
pub(super) fn within_tolerance(
    h: &Hermite,
    before: &[Move],
    after: &[Move],
    leads: &mut [f64; TRANSITION_SAMPLES + 1],
) -> bool {
    let g = Guards::of(h);
    // The moves nearest each half's end of the transition first (the others often need no
    // distance), found once: the first one's distance is kept (`Leads`).
    let move_at = |i: usize| before.get(i).unwrap_or_else(|| &after[i - before.len()]);
    let (n_before, n_after) = (before.len(), after.len());
    let firsts = [0, TRANSITION_SAMPLES].map(|k| move_at(lead(k, n_before, n_after)));
    let mut holds_at = |k: usize| {
        let s = g.sample(h, k);
        let near = |mv: &Move| g.holds(mv, &s, mv.source.distance(s.p));
        let second = 2 * k > TRANSITION_SAMPLES;
        let first = firsts[usize::from(second)];
        // Where a bound tells that the lead holds, unmeasured (most of an arc's samples: no
        // `atan2`); the reported line measures it where it needs the value (source_map.rs).
        if g.held(first, &s) {
            leads[k] = UNMEASURED;
            return true;
        }
        leads[k] = first.source.distance(s.p);
        g.holds(first, &s, leads[k])
            || if !second {
                before.iter().rev().chain(after).skip(1).any(near)
            } else {
                after.iter().chain(before.iter().rev()).skip(1).any(near)
            }
    };
    // From the middle outwards: a cut too long fails first near the apex, where the transition
    // is farthest from both pieces (the cut search tries several before one keeps it).
    let half = TRANSITION_SAMPLES / 2;
    holds_at(half) && (1..=half).all(|i| holds_at(half - i) && holds_at(half + i))
}

//! Whether a piece joins the chain before it (smooth.rs, stage 3): by the time each way costs,
//! with the ramps within the tighter of both sides' limits.

use crate::feed::bands::{Banded, Bands};
use crate::feed::{scurve7_banded, Limits, ProfileKind};

/// Whether a piece of `length` and speed class `class` should join the chain (of `chain_length`
/// at `chain_class`, whose pieces already lose `chain_loss` to it) rather than start the next
/// one, by the time each way costs; the chain's loss if it joins. Joined, the faster side runs
/// at the slower one's speed v_slow over its length L. Apart, it is a block entered and left at
/// v_slow, reaching what it can of its own speed within its length (planned, within the faster
/// side's limits and bands `fast`): that saves L/v_slow − T_block. Their junction is then a
/// block end, where the acceleration is zero: a ramp from rest to the block's peak through it
/// takes T(0, v_slow) + T(v_slow, v_peak) rather than T(0, v_peak), unless each side reaches
/// v_slow from rest within its length (then no ramp need pass through). Joining pays when what the
/// pieces lose to it, added up over the chain, stays within that, also counting the slower
/// ramp within the tighter of the two sides' limits (`slow`, `fast`; the chain's are the worst
/// of its pieces': a 16 µm arc from rest joined to a transition climbing in Z ramped at
/// 45 mm/s² instead of 114; `rest`: the chain starts from rest, a stop (or nearly) follows the
/// piece).
/// Decided on their times, the two ways cost about the same where the choice changes with a
/// limit.
pub(in crate::path) fn joined_loss(
    chain_loss: f64,
    (chain_length, chain_class): (f64, f64),
    (length, class): (f64, f64),
    fast: (&Limits, &Bands),
    slow: (&Limits, &Bands),
    (start, stop): (bool, bool),
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
        top: fast.0,
        bands: fast.1,
    };
    let slow_banded = Banded {
        kind: ProfileKind::Scurve7,
        top: slow.0,
        bands: slow.1,
    };
    // The block's rise from v_slow to its peak is the ramp through the junction's upper part
    // (v_slow is finite and above 0 here, the block's entry as planned).
    let (duration, v_peak, rise) = scurve7_banded::plan_time_rise(&banded, l_fast, v_slow, v_slow, v_fast);
    let loss = chain_loss + (l_fast / v_slow - duration).max(0.0);
    let mut from_rest = None;
    let from_rest = scurve7_banded::Rise::build_in(&mut from_rest, &banded, 0.0);
    let t = |v: f64| from_rest.time_distance(v).0;
    let (t_slow, fast_reach) = from_rest.time_distance(v_slow);
    let through = t_slow + rise - t(v_peak);
    if loss > through {
        return None;
    }
    // The slower side's ramp from rest to its speed within its own limits.
    let (slow_ramp, slow_reach) = if slow == fast {
        (t_slow, fast_reach)
    } else {
        scurve7_banded::ramp(&slow_banded, 0.0, v_slow)
    };
    // Where each side reaches the slower one's speed within its length even from rest at its
    // far end, no ramp need pass through the junction: it is run at that speed, and a block end
    // there costs nothing (an arc of 0.59 mm at 27.6 mm/s joined the transition and arc after
    // it, 2.9 mm that ran at 34 mm/s apart: 0.553 s against 0.535 s at a smaller tolerance).
    let l_slow = if class < chain_class { length } else { chain_length };
    let apart = if slow_reach <= l_slow && fast_reach <= l_fast {
        0.0
    } else {
        through
    };
    // Joined, the chain's limits are the worst of its pieces': where either side's are clearly
    // tighter, a ramp through the chain (from rest, as `apart` counts it) takes longer (the
    // same limits and bands ramp alike): the slower side's, or the faster side's near the
    // slower one's speed, the top of its own budget (a 1.9 mm transition joined to a 31.8 mm
    // arc ramped it at 0.08 m/s² instead of 0.4).
    let (looser, mut tighter) = (slow_ramp.min(t_slow), slow_ramp.max(t_slow));
    // Where a stop follows the piece and its ramp to rest lies within it, joined it ramps within
    // the chain's limits: slower by any margin counts (a 7.8 mm arc ending the program ramped
    // 1.17 times as slow within a 0.49 mm transition's limits and stopped 2.4 ms later).
    // Likewise where the chain starts from rest and its ramp from it lies within the chain (a
    // 22.1 mm arc from rest joined a 0.27 mm transition at its speed: its ramp within the
    // transition's limits, 1.2 times as slow, took 3.3 ms longer).
    let (own, chain_own) = if class < chain_class {
        ((slow_ramp, slow_reach), (t_slow, fast_reach))
    } else {
        ((t_slow, fast_reach), (slow_ramp, slow_reach))
    };
    let stops_within = stop && own.1 <= length && tighter > own.0;
    let starts_within = start && chain_own.1 <= chain_length && tighter > chain_own.0;
    let over = |tighter: f64| {
        if stops_within || starts_within || tighter > TIGHTER_RAMP * looser {
            tighter - looser
        } else {
            0.0
        }
    };
    // Each side's limits may be the tighter at different speeds: the ramp within the worst of
    // both at every speed, where that may decide (`MIXED_RAMP`).
    if slow != fast && loss + over(tighter) <= apart && loss + over(MIXED_RAMP * tighter) > apart {
        tighter = tighter.max(banded.worst_ramp(&slow_banded, v_slow).unwrap_or(0.0));
    }
    let tighter_ramp = over(tighter);
    (loss + tighter_ramp <= apart).then_some(loss)
}

/// The ramp within the worst of two sides' limits at every speed is solved only where this much
/// longer than the tighter side's own would decide: it was at most 1.12 times as long on the
/// CAM-like 10 k lines (1.13 in the found case of tests/monotone_found.rs).
const MIXED_RAMP: f64 = 1.2;

/// A ramp to the slower side's speed this much longer within one side's limits than within the
/// other's counts against joining them (below it, as between the fitted spans of one curve, whose
/// limits differ a little, a chain still pays: they run through at one speed). Likewise a curve
/// fitted over one line whose ramps are this much slower than the line's is not kept (fit.rs).
pub(in crate::path) const TIGHTER_RAMP: f64 = 1.25;

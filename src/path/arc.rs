//! Path limits of arcs and other curves: seed 004 §2.3–2.4 (eq. 17–24) with the chord-error
//! limit of seed 003.

use super::budget::{lower, max_bounds, raise, Budget};
use super::tolerance::{CUBE_MARGIN, NEGLIGIBLE};
use crate::config::Machine;
use crate::feed::bands::{Band, Bands, MAX_BANDS};
use crate::feed::Limits;
use crate::geometry::Arc;
use crate::Vec3;

/// Seed 003: the chord of one interpolation period T at speed v deviates from a circle of radius R
/// by δ when v·T = 2·sqrt(δ(2R − δ)), so v ≤ 2·sqrt(δ(2R − δ))/T.
pub fn chord_error_speed(radius: f64, chord_tolerance: f64, period: f64) -> f64 {
    let d = chord_tolerance.min(radius);
    2.0 * (d * (2.0 * radius - d)).sqrt() / period
}

/// Largest constant speed on a curve whose arc-length derivatives are bounded by `bounds` per axis
/// (axis velocity d1·v, acceleration d2·v², jerk d3·v³ at constant speed; eq. 9 is the circle case:
/// sqrt(A·R), (J·R²)^(1/3)), within the path limits; one ∛, of the least J/d3 (∛ is monotone).
pub fn constant_speed_limit(bounds: &[Vec3; 3], machine: &Machine) -> f64 {
    let mut v = machine.max_feed;
    let (mut d2n, mut d3n, mut x3): (f64, f64, f64) = (0.0, 0.0, f64::INFINITY);
    for (i, ax) in machine.axes.iter().enumerate() {
        let [d1, d2, d3] = [bounds[0][i], bounds[1][i], bounds[2][i]];
        // Compare and select (`lower`, `raise`): v, x3, d2n and d3n are never NaN.
        if d1 > NEGLIGIBLE {
            lower(&mut v, ax.max_velocity / d1);
        }
        if d2 > NEGLIGIBLE {
            lower(&mut v, (ax.max_acceleration / d2).sqrt());
        }
        if d3 > NEGLIGIBLE {
            lower(&mut x3, ax.max_jerk / d3);
        }
        raise(&mut d2n, d2);
        raise(&mut d3n, d3);
    }
    if let (Some(a), true) = (machine.max_path_acceleration, d2n > NEGLIGIBLE) {
        lower(&mut v, (a / d2n).sqrt());
    }
    if let (Some(j), true) = (machine.max_path_jerk, d3n > NEGLIGIBLE) {
        lower(&mut x3, j / d3n);
    }
    min_cbrt(v, x3)
}

/// min(v, ∛x), the root taken only where it may be the smaller: where x exceeds v³ by far more
/// than the rounding of either (`CUBE_MARGIN`), ∛x > v (the same value, without the root's cost).
fn min_cbrt(v: f64, x: f64) -> f64 {
    if x > v * v * v * (1.0 + CUBE_MARGIN) {
        v
    } else {
        v.min(x.cbrt())
    }
}

/// Share of the free acceleration and jerk (A_i/|d1_i|, J_i/|d1_i|) that the tangential law keeps
/// on an arc, at least.
const TANGENTIAL_SHARE: f64 = 0.1;

/// Path limits of an arc (seed 004 §2.4). Start from v_max = min(feed limit, chord error (seed
/// 003), sqrt(A_n·ρ), (J_n·ρ²)^(1/3)) with A_n, J_n the axis limits over the in-plane amplitudes
/// (eq. 9 form, ρ the helix's radius of curvature). The curvilinear acceleration follows eq. 23–24
/// with the centripetal term at v_max, A_c = min_i (A_i − |d2_i|·v²)/|d1_i|, and the curvilinear
/// jerk eq. 19–20 with the chain-rule terms, J_c = min_i (J_i − |d3_i|·v³ − 3|d2_i|·v·A_c)/|d1_i|;
/// the paper evaluates them at the arc ends only, we bound them over the whole sweep. A_c is taken
/// no larger than half its free value nor than what leaves the jerk its share; if A_c or J_c
/// would fall below `TANGENTIAL_SHARE` of their free values, v_max is lowered to where they do not.
/// So axis a = d2·v² + d1·a and j = d3·v³ + 3·d2·v·a + d1·j stay within the axis limits for any
/// v ≤ v_max, |a| ≤ A_c, |j| ≤ J_c.
pub fn arc_limits(arc: &Arc, machine: &Machine) -> Limits {
    let shares = Shares {
        a_cap: 0.5,
        tangential: TANGENTIAL_SHARE,
    };
    let mut cells = Vec::new();
    arc.cells(|c| cells.push(c));
    curve_limits(&cells, arc.curvature_radius(), f64::INFINITY, machine, shares)
}

/// How `curve_limits` splits the axis budgets: A_c at most `a_cap` of its free value, and the
/// tangential acceleration and jerk at least `tangential` of theirs.
#[derive(Clone, Copy, Debug)]
pub struct Shares {
    pub a_cap: f64,
    pub tangential: f64,
}

/// Path limits on any curve whose derivatives w.r.t. its parameter are bounded per axis by
/// `b` (|p'|, |p''|, |p'''|), `rho` its smallest radius of curvature (chord error), as described
/// for arcs above, the speed never above `v_cap`. The largest v_max whose budget keeps the
/// tangential shares is solved in closed form (`Budget::max_speed`: each constraint is monotone).
pub fn curve_limits(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, machine: &Machine, shares: Shares) -> Limits {
    Frame::of(cells, rho, v_cap, machine).limits(cells, machine, shares)
}

/// What every budget of a curve starts from: the speed bound without tangential motion (axis
/// limits, chord error, cap) and the free tangential acceleration and jerk A_i/|d1_i|, J_i/|d1_i|.
/// Worked out once per curve and cap: its top speed, its bands and its ceiling all start here.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    v0: f64,
    a_free: f64,
    j_free: f64,
}

impl Frame {
    /// The frame of the curve with derivative bound cells `cells` and smallest radius of
    /// curvature `rho` (chord error), its speed never above `v_cap`.
    pub fn of(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, machine: &Machine) -> Frame {
        Frame::uncapped(&max_bounds(cells), rho, machine).capped(v_cap)
    }

    /// `of` before its speed is capped (`capped`), given the largest of the cells' bounds
    /// (`max_bounds`).
    pub fn uncapped(b: &[Vec3; 3], rho: f64, machine: &Machine) -> Frame {
        let chord = chord_error_speed(rho, machine.chord_tolerance, machine.interpolation_period);
        let v0 = constant_speed_limit(b, machine).min(chord);
        let (mut a_free, mut j_free) = (f64::INFINITY, f64::INFINITY);
        for (i, ax) in machine.axes.iter().enumerate() {
            if b[0][i] > NEGLIGIBLE {
                a_free = a_free.min(ax.max_acceleration / b[0][i]);
                j_free = j_free.min(ax.max_jerk / b[0][i]);
            }
        }
        if let Some(a) = machine.max_path_acceleration {
            a_free = a_free.min(a);
        }
        if let Some(j) = machine.max_path_jerk {
            j_free = j_free.min(j);
        }
        Frame { v0, a_free, j_free }
    }

    /// The frame with its speed at most `v_cap`.
    pub fn capped(mut self, v_cap: f64) -> Frame {
        self.v0 = self.v0.min(v_cap);
        self
    }

    /// `curve_limits` of its curve (`cells`).
    fn limits(&self, cells: &[[Vec3; 3]], machine: &Machine, shares: Shares) -> Limits {
        let (v, (a_c, j_c)) = self.budget(cells, machine, shares).max_speed(self.v0);
        Limits {
            v_max: v,
            a_max: a_c,
            j_max: j_c,
            snap_max: machine.max_snap,
        }
    }

    /// A bound from above of its curve's `curve_top_speed` without the budget's solves: the
    /// speed with no tangential motion (axis limits at constant speed, chord error, cap), where
    /// every budget's search starts and below which it only falls.
    pub fn ceiling(&self) -> f64 {
        self.v0
    }

    fn budget<'a>(&self, cells: &'a [[Vec3; 3]], machine: &'a Machine, shares: Shares) -> Budget<'a> {
        Budget {
            cells,
            machine,
            a_cap: shares.a_cap * self.a_free,
            j_free: self.j_free,
            a_min: shares.tangential * self.a_free,
            j_min: shares.tangential * self.j_free,
        }
    }
}

/// The whole budget, none kept for the tangential law: where the bands are measured from.
const NO_SHARES: Shares = Shares {
    a_cap: 1.0,
    tangential: 0.0,
};
/// A speed above any a curve allows (m/s): where the search for its budget's end starts.
const CURVE_SPEED_CEILING: f64 = 1e4;
/// Band tops lie on one grid of speeds for every curve, q^n m/s (n whole), the `MAX_BANDS`
/// below its top speed: so a higher feed, axis speed or chord tolerance only adds bands above
/// the ones there were (and drops the lowest, 1/q^MAX_BANDS of the top, where the budget is
/// nearly whole).
const BAND_GRID: f64 = 1.259_921_049_894_873_2; // 2^(1/3)
/// Share of the curve's speed limit (its budget's end) that its top speed may reach.
const TOP_SHARE: f64 = 0.995;
/// A band edge at this share of that top, 0.985 of the budget's end (the top before it rose to
/// `TOP_SHARE`): near its end the budget's acceleration falls steeply (at the top to about 1 %
/// of what the axes leave at half the speed), and without this edge every speed of the top's
/// grid cell would take the top's pair. With it, a curve at its own limit keeps the bands it had
/// with the lower top and gains the speeds above (the CAM-like 100 k lines run 0.7 % faster).
const INNER_EDGE: f64 = 0.99;
/// Relative margin above the curve's top at which its caps no longer lower it (far above the
/// few ulps to which `Budget::max_speed` solves a speed).
const CAP_MARGIN: f64 = 1e-9;
/// Share of the jerk a band's pair leaves (of what is left at zero tangential acceleration).
const BAND_JERK_SHARE: f64 = 0.5;

/// The speeds of a curve's band tops, by increasing speed: the `MAX_BANDS` fastest of the grid
/// speeds below its top and its inner edge (`INNER_EDGE` of v_curve) where that lies below the
/// top; last, the speed of the top's pair (`top_pair_speed`).
fn band_speeds(v_top: f64, v_curve: f64) -> [f64; MAX_BANDS + 1] {
    let inner = INNER_EDGE * v_curve;
    // Still to be placed, stepping down (on the grid itself it is the grid's level).
    let mut inner_left = inner < v_top;
    let mut speeds = [0.0; MAX_BANDS + 1];
    let above = grid_at_or_above(v_top);
    let mut next = above / BAND_GRID;
    for g in speeds[..MAX_BANDS].iter_mut().rev() {
        if inner_left && inner > next {
            *g = inner;
            inner_left = false;
            continue;
        }
        inner_left &= inner != next;
        *g = next;
        next /= BAND_GRID;
    }
    speeds[MAX_BANDS] = top_pair_speed(v_top, v_curve, above);
    speeds
}

/// Where the top band takes its pair: the first at or above the top of the grid speed `above`
/// (`grid_at_or_above` of the top), the inner edge and v_curve (a higher cap leaves it as it was
/// until the top passes it).
fn top_pair_speed(v_top: f64, v_curve: f64, above: f64) -> f64 {
    let inner = INNER_EDGE * v_curve;
    let inner_above = if inner >= v_top { inner } else { f64::INFINITY };
    above.min(inner_above).min(v_curve).max(v_top)
}

/// The smallest grid speed q^n m/s (n whole) at or above v > 0: by multiplying and dividing from
/// 1 m/s (no logarithm, so every platform's libm gives the same grid).
fn grid_at_or_above(v: f64) -> f64 {
    let mut g = 1.0;
    while g < v {
        g *= BAND_GRID;
    }
    while g / BAND_GRID >= v {
        g /= BAND_GRID;
    }
    g
}

/// Limits and speed bands of a curve (feed/bands.rs). v_0 is where the curve's budget ends: the
/// speed with no tangential acceleration or jerk left (the centripetal and chain-rule terms take
/// the axes' acceleration or jerk). The top speed is `TOP_SHARE` of it, within the caps (axis
/// speeds, chord error, feed); the bands end at the grid speeds below it (`BAND_GRID`) and at
/// the inner edge (`INNER_EDGE`) where that lies below it. At a
/// speed v the axes leave A(v) = min_i (A_i − |d2_i|·v²)/|d1_i| and, with acceleration a, the
/// jerk J(v, a) = min_i (J_i − |d3_i|·v³ − 3|d2_i|·v·a)/|d1_i|: more acceleration leaves less
/// jerk. A band ending at v reserves the jerk terms of an acceleration a_r that depends on the
/// jerk limits only — the one leaving `BAND_JERK_SHARE` of J(v, 0), and no more than
/// sqrt(2·v·J(v, 0)), about the most a ramp within the band reaches — and takes
/// (min(A(v), a_r), J(v, a_r)): the acceleration grows with every acceleration limit, the jerk
/// with every jerk limit, and the pair holds at every speed up to v (each term grows with v).
/// The top band takes its pair at the next grid speed or inner edge above the top (or at the
/// top, where the curve itself limits it), so a band's pair does not depend on the caps: a
/// higher cap leaves every band as it was and adds speed above.
/// `known`: what `curve_top_speed` solved for the same curve and cap, where it did (its speeds
/// and the top's pair not solved again).
pub fn curve_bands(
    frame: &Frame,
    cells: &[[Vec3; 3]],
    machine: &Machine,
    known: Option<TopSpeeds>,
) -> (Limits, Bands) {
    let Some(Top {
        budget,
        v_curve,
        v_top,
    }) = top(frame, cells, machine, known.map(|k| k.map(|(speeds, _)| speeds)))
    else {
        return (frame.limits(cells, machine, NO_SHARES), Bands::default());
    };
    let speeds = band_speeds(v_top, v_curve);
    // The top's pair (the last speed's) where `curve_top_speed` found it is not solved again.
    let (a, j, (a_top, j_top)) = match known {
        Some(Some((_, pair))) => {
            let (a, j) = band_pairs::<MAX_BANDS>(&budget, &std::array::from_fn(|k| speeds[k]));
            (a, j, pair)
        }
        _ => {
            let (a, j) = band_pairs(&budget, &speeds);
            let cut = |x: [f64; MAX_BANDS + 1]| std::array::from_fn(|k| x[k]);
            (cut(a), cut(j), (a[MAX_BANDS], j[MAX_BANDS]))
        }
    };
    // Room for every level at once (one allocation, kept by the bands).
    let mut levels = Vec::with_capacity(MAX_BANDS);
    levels.extend((0..MAX_BANDS).filter(|&k| speeds[k] < v_top).map(|k| Band {
        v_top: speeds[k],
        a_max: a[k],
        j_max: j[k],
    }));
    let limits = Limits {
        v_max: v_top,
        a_max: a_top,
        j_max: j_top,
        snap_max: machine.max_snap,
    };
    if a_top <= 0.0 || j_top <= 0.0 {
        return (frame.limits(cells, machine, NO_SHARES), Bands::default());
    }
    (limits, Bands::keep_below(&limits, levels))
}

/// Where a curve's bands start (`curve_bands`): its budget with no shares kept, the speed its
/// top may reach (`TOP_SHARE` of where the budget ends) and its top speed within the caps.
struct Top<'a> {
    budget: Budget<'a>,
    v_curve: f64,
    v_top: f64,
}

/// The speeds a curve's `Top` was solved to (v_curve, v_top) and the top band's pair there
/// (`top_pair_speed`), or None where it has no budget: kept by whoever asks for the top speed first
/// and the bands later (junction.rs).
pub type TopSpeeds = Option<((f64, f64), (f64, f64))>;

/// The curve's `Top`, or None where it has no budget (its plain limits then), from its speeds
/// (v_curve, v_top) where they are `known`.
fn top<'a>(
    frame: &Frame,
    cells: &'a [[Vec3; 3]],
    machine: &'a Machine,
    known: Option<Option<(f64, f64)>>,
) -> Option<Top<'a>> {
    let budget = frame.budget(cells, machine, NO_SHARES);
    let speeds = known.unwrap_or_else(|| {
        let v_zero = budget.max_speed(CURVE_SPEED_CEILING).0;
        let v_curve = TOP_SHARE * v_zero;
        // The speed within the caps is the cap or the budget's end, each as solved to a few
        // ulps: with the caps well above the curve's top, it is above that top too, and not
        // solved; below it, they are below the end by far more than rounding (`TOP_SHARE`).
        let v_top = if frame.v0 >= v_curve * (1.0 + CAP_MARGIN) {
            v_curve
        } else {
            v_curve.min(budget.max_speed_below_end(frame.v0).0)
        };
        (v_top > 0.0 && v_top.is_finite()).then_some((v_curve, v_top))
    });
    speeds.map(|(v_curve, v_top)| Top {
        budget,
        v_curve,
        v_top,
    })
}

/// The top speed of `curve_bands`' limits alone: the top band's pair decides whether the curve
/// has bands (the pair of each other band is not needed for it).
/// Also what it solved for the top (`TopSpeeds`), which `curve_bands` takes.
pub fn curve_top_speed(frame: &Frame, cells: &[[Vec3; 3]], machine: &Machine) -> (f64, TopSpeeds) {
    let plain = || frame.limits(cells, machine, NO_SHARES).v_max;
    let Some(t) = top(frame, cells, machine, None) else {
        return (plain(), None);
    };
    let above = grid_at_or_above(t.v_top);
    let (a, j) = band_pairs(&t.budget, &[top_pair_speed(t.v_top, t.v_curve, above)]);
    let (a, j) = (a[0], j[0]);
    let solved = Some(((t.v_curve, t.v_top), (a, j)));
    if a <= 0.0 || j <= 0.0 {
        (plain(), solved)
    } else {
        (t.v_top, solved)
    }
}

/// The pair (A, J) a band ending at each speed of `v` takes (`curve_bands`): the acceleration
/// reserved for the jerk terms is the one leaving `BAND_JERK_SHARE` of J(v, 0), at most about
/// the most a ramp within the band reaches, sqrt(2·v·J(v, 0)). Both come from the jerk limits
/// alone: reserved up to the free acceleration instead, a higher acceleration limit took jerk
/// from the band, and a single arc from rest ran longer (0.15 % at 1.66× every acceleration).
/// J is then the jerk left with the reserve; A, the reserve within the free acceleration.
fn band_pairs<const N: usize>(budget: &Budget, v: &[f64; N]) -> ([f64; N], [f64; N]) {
    let (a_free, j0) = budget.free_at(v);
    let j_share = j0.map(|j| BAND_JERK_SHARE * j);
    let a_reach: [f64; N] = std::array::from_fn(|k| (2.0 * v[k] * j0[k].max(0.0)).sqrt());
    // a_jerk is taken only within a_reach: from just above it (the next float, or ∞ where it is
    // NaN), the minimum is the same where a_jerk ≤ a_reach and stays above a_reach where not.
    let above = a_reach.map(|a| if a.is_nan() { f64::INFINITY } else { a.next_up() });
    let a_jerk = budget.acceleration_leaving(v, &j_share, &above);
    // Reserving for a_jerk leaves exactly j_share (its cell binds); for less, what is left.
    let reserved: [f64; N] = std::array::from_fn(|k| a_jerk[k].min(a_reach[k]));
    let left = budget.jerk_with(v, &reserved);
    let a = std::array::from_fn(|k| a_free[k].min(reserved[k]));
    let j = std::array::from_fn(|k| {
        if a_jerk[k] <= a_reach[k] {
            left[k].max(j_share[k])
        } else {
            left[k]
        }
    });
    (a, j)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{norm, Plane};
    use crate::path::testing;
    use crate::si::MM;

    /// `curve_bands` as it was before its pairs ran in one pass (each pair by three scalar passes
    /// over the cells with `f64::min`, both speed solves always): the reference for bit equality.
    fn bands_by_scalar_passes(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, m: &Machine) -> (Limits, Bands) {
        let frame = Frame::of(cells, rho, v_cap, m);
        let budget = frame.budget(cells, m, NO_SHARES);
        let v_zero = budget.max_speed(CURVE_SPEED_CEILING).0;
        let v_curve = TOP_SHARE * v_zero;
        let v_top = v_curve.min(budget.max_speed(frame.v0).0);
        let plain = || (curve_limits(cells, rho, v_cap, m, NO_SHARES), Bands::default());
        if v_top <= 0.0 || !v_top.is_finite() {
            return plain();
        }
        let min_over = |f: &dyn Fn(&crate::config::AxisLimits, [f64; 3]) -> Option<f64>, start: f64| {
            let mut x = start;
            for cell in cells {
                for (i, ax) in m.axes.iter().enumerate() {
                    let d = [cell[0][i], cell[1][i], cell[2][i]];
                    if d[0] > NEGLIGIBLE {
                        if let Some(y) = f(ax, d) {
                            x = x.min(y);
                        }
                    }
                }
            }
            x
        };
        let pair = |v: f64| {
            let a_free = min_over(
                &|ax, [d1, d2, _]| Some((ax.max_acceleration - d2 * v * v) / d1),
                budget.a_cap,
            );
            let j0 = min_over(
                &|ax, [d1, _, d3]| Some((ax.max_jerk - d3 * v * v * v) / d1),
                budget.j_free,
            );
            let j_share = BAND_JERK_SHARE * j0;
            let a_jerk = min_over(
                &|ax, [d1, d2, d3]| {
                    (d2 * v > NEGLIGIBLE)
                        .then(|| (ax.max_jerk - d3 * v * v * v - d1 * j_share) / (3.0 * d2 * v))
                },
                f64::INFINITY,
            );
            let a_reach = (2.0 * v * j0.max(0.0)).sqrt();
            let jerk_with = |a: f64| {
                min_over(
                    &|ax, [d1, d2, d3]| Some((ax.max_jerk - d3 * v * v * v - 3.0 * d2 * v * a) / d1),
                    budget.j_free,
                )
            };
            let (reserved, j) = if a_jerk <= a_reach {
                (a_jerk, jerk_with(a_jerk).max(j_share))
            } else {
                (a_reach, jerk_with(a_reach))
            };
            (a_free.min(reserved), j)
        };
        // Every candidate edge, sorted: the grid below the top and the inner edge.
        let above = grid_at_or_above(v_top);
        let mut edges = Vec::new();
        let mut v = above;
        for _ in 0..MAX_BANDS {
            v /= BAND_GRID;
            edges.push(v);
        }
        edges.push(INNER_EDGE * v_curve);
        edges.retain(|&e| e < v_top);
        edges.sort_by(f64::total_cmp);
        edges.dedup();
        let edges = &edges[edges.len().saturating_sub(MAX_BANDS)..];
        let levels: Vec<Band> = edges
            .iter()
            .map(|&e| {
                let (a, j) = pair(e);
                Band {
                    v_top: e,
                    a_max: a,
                    j_max: j,
                }
            })
            .collect();
        let at = [above, INNER_EDGE * v_curve, v_curve]
            .into_iter()
            .filter(|&e| e >= v_top)
            .fold(f64::INFINITY, f64::min)
            .max(v_top);
        let (a, j) = pair(at);
        if a <= 0.0 || j <= 0.0 {
            return plain();
        }
        let limits = Limits {
            v_max: v_top,
            a_max: a,
            j_max: j,
            snap_max: m.max_snap,
        };
        (limits, Bands::keep_below(&limits, levels))
    }

    /// The band pairs in one pass, the capped speed solved only near the top and the top speed
    /// alone (`curve_top_speed`) give what the scalar passes give, bit for bit, on 400 random
    /// curves (cells with zero and non-zero bounds, random axis limits) and caps from far below
    /// the top to above it, at and around `CAP_MARGIN`; then 400 more, mostly at their own speed
    /// limit, for the inner edge.
    #[test]
    fn band_pairs_equal_the_scalar_passes() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let (mut banded, mut inner_edges) = (0, 0);
        // Curves mostly capped by the axis speeds, then mostly at their own limit (near which
        // the inner edge lies).
        for own_limit in [false, true].into_iter().flat_map(|l| [l; 400]) {
            let mut m = testing::machine(&mut s);
            if own_limit {
                m.max_feed *= 100.0;
                m.axes.iter_mut().for_each(|ax| ax.max_velocity *= 100.0);
            }
            let cells = testing::cells(&mut s, 10, 2.0, -1.5);
            let k = norm(max_bounds(&cells)[1]);
            let rho = if k > 0.0 { 1.0 / k } else { f64::INFINITY };
            let top = bands_by_scalar_passes(&cells, rho, f64::INFINITY, &m).0.v_max;
            for cap in [
                f64::INFINITY,
                0.3 * top,
                top,
                top * (1.0 + 5e-10),
                top * (1.0 + 2e-9),
                2.0 * top,
            ] {
                let frame = Frame::of(&cells, rho, cap, &m);
                let ours = curve_bands(&frame, &cells, &m, None);
                let reference = bands_by_scalar_passes(&cells, rho, cap, &m);
                assert_eq!(format!("{ours:?}"), format!("{reference:?}"), "cap {cap}");
                assert_eq!(ours.0.v_max.to_bits(), reference.0.v_max.to_bits());
                let levels = |b: &Bands| {
                    b.levels()
                        .iter()
                        .map(|l| [l.v_top, l.a_max, l.j_max].map(f64::to_bits))
                        .collect::<Vec<_>>()
                };
                assert_eq!(levels(&ours.1), levels(&reference.1));
                let (top_speed, speeds) = curve_top_speed(&frame, &cells, &m);
                assert_eq!(top_speed.to_bits(), ours.0.v_max.to_bits());
                let known = curve_bands(&frame, &cells, &m, Some(speeds));
                assert_eq!(format!("{known:?}"), format!("{ours:?}"), "cap {cap}");
                assert!(frame.ceiling() >= ours.0.v_max);
                banded += usize::from(!ours.1.is_empty());
                let off_grid = |l: &Band| grid_at_or_above(l.v_top) != l.v_top;
                inner_edges += ours.1.levels().iter().filter(|l| off_grid(l)).count();
            }
        }
        assert!(banded > 1000, "too few curves with bands: {banded}");
        assert!(inner_edges > 500, "too few inner edges: {inner_edges}");
    }

    #[test]
    fn chord_error_limit_r10_delta1um() {
        // Seed 003: v = 2·sqrt(δ(2R − δ))/T, R = 10 mm, δ = 1 µm, T = 1 ms → 0.28283 m/s.
        let v = chord_error_speed(10.0 * MM, 1e-6, 1e-3);
        let expected = 2.0 * (1e-6f64 * (20.0e-3 - 1e-6)).sqrt() / 1e-3;
        assert!((v - expected).abs() < 1e-15);
        assert!((v - 0.282_835).abs() < 1e-6);
        // The chord of one period at that speed deviates from the arc by exactly δ.
        let r = 10.0 * MM;
        let half = v * 1e-3 / 2.0;
        let sagitta = r - (r * r - half * half).sqrt();
        assert!((sagitta - 1e-6).abs() < 1e-12);
    }

    #[test]
    fn arc_limits_keep_axis_limits() {
        let m = Machine::default();
        for r_mm in [0.5, 2.0, 10.0, 100.0] {
            let r = r_mm * MM;
            let arc = Arc::from_gcode([r, 0.0, 0.0], [-r, 0.0, 0.0], [0.0; 3], Plane::XY, false, 0).unwrap();
            let lim = arc_limits(&arc, &m);
            let v = lim.v_max;
            // eq. 9 bounds and the chord limit hold.
            assert!(v <= (2.0 * r).sqrt() + 1e-12);
            assert!(v <= (50.0 * r * r).cbrt() + 1e-12);
            assert!(v <= chord_error_speed(r, m.chord_tolerance, m.interpolation_period) + 1e-12);
            assert!(lim.a_max > 0.0 && lim.j_max > 0.0);
            // Worst case of the chain rule over the arc, with the tangential law at its limits.
            for i in 0..=64 {
                let g = arc.eval(arc.length() * i as f64 / 64.0);
                for (ax, axis) in m.axes.iter().enumerate() {
                    let acc = g.d2[ax].abs() * v * v + g.d1[ax].abs() * lim.a_max;
                    let jerk = g.d3[ax].abs() * v.powi(3)
                        + 3.0 * g.d2[ax].abs() * v * lim.a_max
                        + g.d1[ax].abs() * lim.j_max;
                    assert!(acc <= axis.max_acceleration * (1.0 + 1e-9), "r {r_mm} acc {acc}");
                    assert!(jerk <= axis.max_jerk * (1.0 + 1e-9), "r {r_mm} jerk {jerk}");
                }
            }
        }
    }
}

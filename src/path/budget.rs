//! The axis budgets of a curve at a path speed v: what the centripetal and chain-rule terms of
//! each derivative-bound cell leave for the tangential acceleration A_c and jerk J_c
//! (`curve_limits` in arc.rs), and the largest v at which both keep their shares — each
//! constraint is monotone in v and solved in closed form.

use super::tolerance::{FIT_STEPS, NEGLIGIBLE, SHARE_SLACK};
use crate::config::{AxisLimits, Machine};
use crate::feed::roots::cubic_pos;
use crate::feed::{greater, lesser};
use crate::Vec3;

/// The budgets of one curve: cells of per-axis bounds (|p'|, |p''|, |p'''|) over its parameter,
/// A_c at most `a_cap`, and the shares A_c ≥ `a_min`, J_c ≥ `j_min` the tangential law keeps.
pub struct Budget<'a> {
    pub cells: &'a [[Vec3; 3]],
    pub machine: &'a Machine,
    pub a_cap: f64,
    pub j_free: f64,
    pub a_min: f64,
    pub j_min: f64,
}

impl Budget<'_> {
    /// (A_c, J_c) at speed v, or None when either falls below its share. Each cell bounds p',
    /// p'' and p''' at the same points, so the centripetal and tangential parts add per cell.
    pub fn at(&self, v: f64) -> Option<(f64, f64)> {
        let axes = &self.machine.axes;
        // A_c and J_c start at a_cap and j_free, never NaN: `lower` takes what `f64::min` took.
        let mut a_c = self.a_cap;
        for cell in self.cells {
            for (i, ax) in axes.iter().enumerate() {
                let [d1, d2, d3] = [cell[0][i], cell[1][i], cell[2][i]];
                if d1 > NEGLIGIBLE {
                    lower(&mut a_c, (ax.max_acceleration - d2 * v * v) / d1);
                    // Leave the jerk its share: d3·v³ + 3·d2·v·a + d1·j_min ≤ J_i.
                    if d2 * v > NEGLIGIBLE {
                        lower(
                            &mut a_c,
                            (ax.max_jerk - d3 * v * v * v - d1 * self.j_min) / (3.0 * d2 * v),
                        );
                    }
                } else if d2 * v * v > ax.max_acceleration || d3 * v * v * v > ax.max_jerk {
                    return None;
                }
            }
        }
        // The shares are what makes a budget worth having, not limits (A_c and J_c are the axis
        // budgets as computed): a relative slack keeps rounding from punching holes in the set
        // of speeds that have one (where A_c is the jerk term, J_c = j_min exactly). A_c's share
        // is checked first: where it fails, J_c is not worked out.
        let a_kept = a_c >= self.a_share();
        if !a_kept {
            return None;
        }
        let mut j_c = self.j_free;
        for cell in self.cells {
            for (i, ax) in axes.iter().enumerate() {
                let [d1, d2, d3] = [cell[0][i], cell[1][i], cell[2][i]];
                if d1 > NEGLIGIBLE {
                    lower(&mut j_c, (ax.max_jerk - d3 * v * v * v - 3.0 * d2 * v * a_c) / d1);
                }
            }
        }
        (j_c >= self.j_min * (1.0 - SHARE_SLACK)).then_some((a_c, j_c))
    }

    /// A_c's share as `at` checks it: `a_min` less the slack `SHARE_SLACK`.
    fn a_share(&self) -> f64 {
        self.a_min * (1.0 - SHARE_SLACK)
    }

    /// At each speed v of `v` (each ≥ 0, ascending): the largest tangential acceleration the
    /// centripetal terms leave (at most `a_cap`), min_i (A_i − |d2_i|·v²)/|d1_i|, and the jerk
    /// left with no tangential acceleration (at most `j_free`), min_i (J_i − |d3_i|·v³)/|d1_i|. All
    /// speeds in one pass over the cells (the inner loop over speeds runs in SIMD lanes; each
    /// value is the scalar one), each group of speeds skipping the cells that cannot lower it
    /// (`lower_falling`: each term falls as v rises, every rounded step being monotone).
    // Not inlined: inlined into the top speed's pass at one speed, that pass cost 5 M more.
    #[inline(never)]
    pub fn free_at<const N: usize>(&self, v: &[f64; N]) -> ([f64; N], [f64; N]) {
        debug_assert!(v.is_sorted());
        let (mut a_c, mut j_c) = ([self.a_cap; N], [self.j_free; N]);
        self.each_moving(|ax, [d1, d2, d3]| {
            let a = |k: usize| (ax.max_acceleration - d2 * v[k] * v[k]) / d1;
            let j = |k: usize| (ax.max_jerk - d3 * v[k] * v[k] * v[k]) / d1;
            lower_falling(&mut a_c, a);
            lower_falling(&mut j_c, j);
        });
        (a_c, j_c)
    }

    /// At each speed v of `v` (each ≥ 0), the tangential jerk left with tangential acceleration
    /// up to a (`a`, at most `j_free`): J_c = min_i (J_i − |d3_i|·v³ − 3|d2_i|·v·a)/|d1_i| over
    /// the cells.
    pub fn jerk_with<const N: usize>(&self, v: &[f64; N], a: &[f64; N]) -> [f64; N] {
        let (mut j_c, mut most) = ([self.j_free; N], [self.j_free; N]);
        let (v_high, a_high) = (group_max(v, f64::NEG_INFINITY), group_max(a, 0.0));
        self.each_moving(|ax, [d1, d2, d3]| {
            let j = |v: f64, a: f64| (ax.max_jerk - d3 * v * v * v - 3.0 * d2 * v * a) / d1;
            // Each rounded step is monotone: at most the group's highest v and a (a ≥ 0, so the
            // product with 3·d2·v ≥ 0 only grows), the term is no smaller than at those.
            lower_where_may(
                &mut j_c,
                &mut most,
                |g| j(v_high[g], a_high[g]),
                |k| j(v[k], a[k]),
            );
        });
        j_c
    }

    /// At each speed v of `v` (each ≥ 0), the largest tangential acceleration that leaves the
    /// jerk at least j (`j`): min_i (J_i − |d3_i|·v³ − |d1_i|·j)/(3|d2_i|·v) over the cells, from
    /// the jerk limits alone (not capped by `a_cap`, which comes from the acceleration limits);
    /// the lane of `above` where that is smaller (the same minimum where it is not).
    pub fn acceleration_leaving<const N: usize>(
        &self,
        v: &[f64; N],
        j: &[f64; N],
        above: &[f64; N],
    ) -> [f64; N] {
        let (mut a_c, mut most) = (*above, group_max(above, f64::NEG_INFINITY));
        let (v_high, j_high) = (group_max(v, f64::NEG_INFINITY), group_max(j, f64::NEG_INFINITY));
        self.each_moving(|ax, [d1, d2, d3]| {
            // At the group's highest v and j the numerator is no larger and the denominator no
            // smaller than at any of its speeds: where that numerator is ≥ 0, so is the bound.
            let bound = |g: usize| {
                let (v, j) = (v_high[g], j_high[g]);
                let left = ax.max_jerk - d3 * v * v * v - d1 * j;
                if left >= 0.0 {
                    left / (3.0 * d2 * v)
                } else {
                    f64::NEG_INFINITY
                }
            };
            lower_where_may(&mut a_c, &mut most, bound, |k| {
                let (v, j) = (v[k], j[k]);
                let a = (ax.max_jerk - d3 * v * v * v - d1 * j) / (3.0 * d2 * v);
                if d2 * v > NEGLIGIBLE {
                    a
                } else {
                    f64::INFINITY
                }
            });
        });
        a_c
    }

    /// (axis, [|d1|, |d2|, |d3|]) of each cell and axis that moves (|d1| above `NEGLIGIBLE`).
    #[inline(always)]
    fn each_moving(&self, mut take: impl FnMut(&AxisLimits, Vec3)) {
        for cell in self.cells {
            for (i, ax) in self.machine.axes.iter().enumerate() {
                let d = [cell[0][i], cell[1][i], cell[2][i]];
                if d[0] > NEGLIGIBLE {
                    take(ax, d);
                }
            }
        }
    }

    /// The largest v ≤ `v0` with a budget, and the budget there; (0, shares) if none. Per cell and
    /// axis, each condition of `at` bounds v from above:
    /// - moving axis (d1 > 0): (A − d2·v²)/d1 ≥ a_min ⟺ v ≤ sqrt((A − d1·a_min)/d2), and the jerk
    ///   term ≥ a_min ⟺ d3·v³ + 3·d2·a_min·v ≤ J − d1·j_min, a cubic with one positive root (its
    ///   left side increases in v); J_c ≥ j_min then follows, as A_c is at most that term;
    /// - axis not moving: d2·v² ≤ A and d3·v³ ≤ J.
    pub fn max_speed(&self, v0: f64) -> (f64, (f64, f64)) {
        // The share of A_c as `at` checks it (J_c's follows from A_c's jerk term).
        let a_min = self.a_share();
        let mut v = self.start(v0);
        // The bound that last lowered v (cell, axis, jerk or not): where it leaves no budget,
        // `settle` does not ask `at`.
        let mut binds = None;
        for cell in self.cells {
            for (i, ax) in self.machine.axes.iter().enumerate() {
                let [d1, d2, d3] = [cell[0][i], cell[1][i], cell[2][i]];
                // Each bound is solved only where it binds at the speed found so far (v only
                // falls): most cells of a curve do not, and the roots are the costly part.
                let (a_left, j_left, c) = if d1 > NEGLIGIBLE {
                    let a_left = ax.max_acceleration - d1 * a_min;
                    (a_left, ax.max_jerk - d1 * self.j_min, 3.0 * d2 * a_min)
                } else {
                    (ax.max_acceleration, ax.max_jerk, 0.0)
                };
                if d2 * v * v > a_left {
                    let root = speed_for(d2, 2, a_left);
                    binds = if root < v { Some((cell, i, false)) } else { binds };
                    v = v.min(root);
                }
                if (d3 * v * v + c) * v > j_left {
                    let root = jerk_speed(d3, c, j_left);
                    binds = if root < v { Some((cell, i, true)) } else { binds };
                    v = v.min(root);
                }
            }
        }
        let misses = |w| binds.is_some_and(|(cell, i, jerk)| self.misses(cell, i, jerk, w));
        self.settle(v.max(0.0), misses)
    }

    /// Whether the bound of cell `cell` and axis i (its jerk term, or its acceleration term)
    /// alone leaves `at` no budget at v: the same terms as there, where A_c falls to at most
    /// the term, below its share, or a still axis runs over its limit.
    fn misses(&self, cell: &[Vec3; 3], i: usize, jerk: bool, v: f64) -> bool {
        let ax = &self.machine.axes[i];
        let [d1, d2, d3] = [cell[0][i], cell[1][i], cell[2][i]];
        if d1 <= NEGLIGIBLE {
            return if jerk {
                d3 * v * v * v > ax.max_jerk
            } else {
                d2 * v * v > ax.max_acceleration
            };
        }
        let term = if !jerk {
            (ax.max_acceleration - d2 * v * v) / d1
        } else if d2 * v > NEGLIGIBLE {
            (ax.max_jerk - d3 * v * v * v - d1 * self.j_min) / (3.0 * d2 * v)
        } else {
            return false;
        };
        term < self.a_share()
    }

    /// `max_speed` of a `v0` below the end that `max_speed` found from above by far more than
    /// rounding (as the top speed in arc.rs is): each bound's left side grows with v, so none
    /// binds there, and only `at` is checked (the same speed and budget, without the solves).
    pub fn max_speed_below_end(&self, v0: f64) -> (f64, (f64, f64)) {
        self.settle(self.start(v0).max(0.0), |_| false)
    }

    /// Where a search for the largest speed starts: `v0`, or 0 where the cap leaves A_c less
    /// than its share (`a_share`) at every speed.
    fn start(&self, v0: f64) -> f64 {
        if self.a_cap >= self.a_share() {
            v0
        } else {
            0.0
        }
    }

    /// The largest speed at or a few ulps below `v` (≥ 0) that has a budget, and the budget there.
    /// Rounding may leave the closed form a hair outside the budget as `at` evaluates it (and
    /// `at` skips the jerk term below NEGLIGIBLE): step down from a few ulps, doubling. `at` is
    /// not asked where `misses` already says it has no budget.
    fn settle(&self, v: f64, misses: impl Fn(f64) -> bool) -> (f64, (f64, f64)) {
        let mut w = v;
        let mut step = v * f64::EPSILON;
        for _ in 0..FIT_STEPS {
            if let Some(found) = (!misses(w)).then(|| self.at(w)).flatten() {
                return (w, found);
            }
            w = (w - step).max(0.0);
            step *= 2.0;
        }
        (0.0, self.at(0.0).unwrap_or((self.a_min, self.j_min)))
    }
}

/// Speeds of the loops above taken together: a group's lanes are lowered by a cell only where a
/// bound of its terms there from below does not exceed all of them.
const GROUP: usize = 16;

/// At each whole group's first lane, the largest of its lanes of `x` and `floor`, NaN lanes
/// left out (their terms are NaN, which lowers nothing).
#[inline(always)]
fn group_max<const N: usize>(x: &[f64; N], floor: f64) -> [f64; N] {
    let mut high = [floor; N];
    for g in (0..N / GROUP).map(|g| g * GROUP) {
        high[g] = x[g..g + GROUP].iter().fold(floor, |m, &y| m.max(y));
    }
    high
}

/// The largest lane of a group of minima, halved pairwise so that it runs in SIMD lanes (a
/// compare and select: its lanes are all NaN or none, as a NaN start stays and `lower` takes no
/// NaN).
#[inline(always)]
fn largest(x: &[f64]) -> f64 {
    let mut w = [0.0; GROUP];
    w.copy_from_slice(x);
    let mut n = GROUP;
    while n > 1 {
        n /= 2;
        for i in 0..n {
            w[i] = if w[i] > w[i + n] { w[i] } else { w[i + n] };
        }
    }
    w[0]
}

/// `lower_where_may` where the lanes and the terms fall (or stay) from lane to lane: the lanes
/// start equal and each term falls as the speed rises (ascending speeds; the bounds of a curve
/// are finite, so no term is NaN in some lanes only), so that every lane stays at most its
/// group's first (its largest) and each term at least its group's last (its smallest).
#[inline(always)]
fn lower_falling<const N: usize>(acc: &mut [f64; N], term: impl Fn(usize) -> f64) {
    for g in (0..N / GROUP).map(|g| g * GROUP) {
        if term(g + GROUP - 1) > acc[g] {
            continue;
        }
        (g..g + GROUP).for_each(|k| lower(&mut acc[k], term(k)));
    }
    (N / GROUP * GROUP..N).for_each(|k| lower(&mut acc[k], term(k)));
}

/// `lower` of each lane k of `acc` by `term(k)`, where `most` holds at each group's first lane
/// at least the largest of its lanes: a whole group (from lane g) is skipped where `bound(g)`,
/// no larger than any of its terms, exceeds that (none of them would lower a lane: the same
/// values, as lanes only fall). Lanes past the last whole group are lowered one by one.
#[inline(always)]
fn lower_where_may<const N: usize>(
    acc: &mut [f64; N],
    most: &mut [f64; N],
    bound: impl Fn(usize) -> f64,
    term: impl Fn(usize) -> f64,
) {
    for g in (0..N / GROUP).map(|g| g * GROUP) {
        if bound(g) > most[g] {
            continue;
        }
        (g..g + GROUP).for_each(|k| lower(&mut acc[k], term(k)));
        most[g] = largest(&acc[g..g + GROUP]);
    }
    (N / GROUP * GROUP..N).for_each(|k| lower(&mut acc[k], term(k)));
}

/// acc = min(acc, x) for an acc that is not NaN (`lesser`: a NaN x leaves acc).
#[inline(always)]
pub(super) fn lower(acc: &mut f64, x: f64) {
    *acc = lesser(x, *acc);
}

/// acc = max(acc, x) likewise (`greater`).
#[inline(always)]
pub(super) fn raise(acc: &mut f64, x: f64) {
    *acc = greater(x, *acc);
}

/// Largest v ≥ 0 with d·v^n ≤ left (∞ if d is 0, 0 if nothing is left).
fn speed_for(d: f64, n: i32, left: f64) -> f64 {
    if left < 0.0 {
        0.0
    } else if d <= 0.0 {
        f64::INFINITY
    } else if n == 2 {
        (left / d).sqrt()
    } else {
        (left / d).cbrt()
    }
}

/// Largest v ≥ 0 with d3·v³ + c·v ≤ left (c ≥ 0): the positive root of v³ + (c/d3)·v − left/d3.
fn jerk_speed(d3: f64, c: f64, left: f64) -> f64 {
    if left < 0.0 {
        0.0
    } else if d3 > 0.0 {
        cubic_pos(c / d3, left / d3)
    } else if c > 0.0 {
        left / c
    } else {
        f64::INFINITY
    }
}

/// Largest per-axis bounds over the cells.
pub fn max_bounds(cells: &[[Vec3; 3]]) -> [Vec3; 3] {
    let mut b = [[0.0f64; 3]; 3];
    for cell in cells {
        raise_bounds(&mut b, cell);
    }
    b
}

/// Each bound of `b` raised to the cell's where that is larger (`raise`).
#[inline(always)]
pub(super) fn raise_bounds(b: &mut [Vec3; 3], cell: &[Vec3; 3]) {
    for (acc, new) in b.iter_mut().zip(cell) {
        for i in 0..3 {
            raise(&mut acc[i], new[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::testing;
    use crate::test_rng::unit;

    /// The budget of `cells` on `machine` with `tangential` of the free acceleration and jerk
    /// kept for the path (the shares), A_c at most `a_cap`.
    fn shared<'a>(
        cells: &'a [[Vec3; 3]],
        machine: &'a Machine,
        a_cap: f64,
        (a_free, j_free): (f64, f64),
        tangential: f64,
    ) -> Budget<'a> {
        Budget {
            cells,
            machine,
            a_cap,
            j_free,
            a_min: tangential * a_free,
            j_min: tangential * j_free,
        }
    }

    /// The closed-form speed equals the 32-step bisection it replaced (to its 2⁻³² of v0) on 1000
    /// random curves: cells with zero and non-zero bounds, random axis limits and shares.
    #[test]
    fn max_speed_matches_the_bisection_it_replaced() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut lowered = 0;
        for _ in 0..1000 {
            let machine = testing::machine(&mut s);
            let cells = testing::cells(&mut s, 6, 3.0, -1.0);
            let tangential = [0.005, 0.05, 0.1, 0.25][(unit(&mut s) * 4.0) as usize];
            let (a_free, j_free) = (1.0 + 5.0 * unit(&mut s), 10.0 + 100.0 * unit(&mut s));
            let budget = shared(
                &cells,
                &machine,
                [0.5, 1.0][(unit(&mut s) * 2.0) as usize] * a_free,
                (a_free, j_free),
                tangential,
            );
            let v0 = 0.01 + unit(&mut s);
            // The old routine: v0 if it has a budget, else 32 bisection steps on [0, v0].
            let old = if budget.at(v0).is_some() {
                v0
            } else {
                lowered += 1;
                let (mut lo, mut hi) = (0.0, v0);
                for _ in 0..32 {
                    let mid = 0.5 * (lo + hi);
                    if budget.at(mid).is_some() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            let (new, found) = budget.max_speed(v0);
            assert!(new <= v0);
            if new > 0.0 {
                assert_eq!(budget.at(new), Some(found), "a budget at the speed returned");
            }
            // The bisection's last good point is below the boundary by at most v0·2⁻³².
            assert!(new >= old, "{new} < bisection {old}");
            assert!(
                new - old <= v0 * 2f64.powi(-32) * (1.0 + 1e-9),
                "{new} vs bisection {old}"
            );
        }
        assert!(lowered > 200, "too few curves lowered below v0: {lowered}");
    }

    /// Where `misses` says a cell's bound leaves no budget, `at` finds none: random curves, shares
    /// and speeds about each bound's end (`settle` does not ask `at` there).
    #[test]
    fn a_missed_bound_leaves_no_budget() {
        let mut s = 0x51_7cc1_b727_220au64;
        let mut missed = 0;
        for _ in 0..1000 {
            let machine = testing::machine(&mut s);
            let cells = testing::cells(&mut s, 6, 3.0, -1.0);
            let tangential = [0.0, 0.05, 0.25][(unit(&mut s) * 3.0) as usize];
            let (a_free, j_free) = (1.0 + 5.0 * unit(&mut s), 10.0 + 100.0 * unit(&mut s));
            let budget = shared(&cells, &machine, a_free, (a_free, j_free), tangential);
            let end = budget.max_speed(1e4).0;
            for (cell, i, jerk) in (0..cells.len()).flat_map(|c| (0..6).map(move |k| (c, k / 2, k % 2 == 1)))
            {
                let w = end
                    * (1.0 + 1e-15 * (unit(&mut s) - 0.5))
                    * [1.0, 1.01, 0.99][(unit(&mut s) * 3.0) as usize];
                if budget.misses(&cells[cell], i, jerk, w) {
                    missed += 1;
                    assert_eq!(budget.at(w), None, "cell {cell} axis {i} jerk {jerk} at {w}");
                }
            }
        }
        assert!(missed > 1000, "too few missed bounds: {missed}");
    }

    /// Below the end that `max_speed` finds from above (at `TOP_SHARE` of it, as the top speed in
    /// arc.rs), `max_speed_below_end` gives what `max_speed` gives, bit for bit.
    #[test]
    fn below_the_end_the_solves_are_not_needed() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..1000 {
            let machine = testing::machine(&mut s);
            let cells = testing::cells(&mut s, 6, 3.0, -1.0);
            let (a_free, j_free) = (1.0 + 5.0 * unit(&mut s), 10.0 + 100.0 * unit(&mut s));
            let tangential = [0.0, 0.1][(unit(&mut s) * 2.0) as usize];
            let budget = shared(&cells, &machine, a_free, (a_free, j_free), tangential);
            let end = budget.max_speed(1e4).0;
            for v0 in [0.995 * end, 0.5 * end, 0.0] {
                let bits = |(v, (a, j)): (f64, (f64, f64))| [v, a, j].map(f64::to_bits);
                assert_eq!(bits(budget.max_speed(v0)), bits(budget.max_speed_below_end(v0)));
            }
        }
    }
}

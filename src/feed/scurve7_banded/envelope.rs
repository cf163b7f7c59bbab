//! The fastest rise lo → hi under speed bands as constant-jerk pieces in the phase plane (see
//! the module comment of scurve7_banded.rs): min of the forward envelope F (from a = 0 at lo) and
//! the backward envelope B (from a = 0 at hi).
//!
//! F depends on lo alone: below the band of hi its pieces are those of any rise from lo, and in
//! that band they are clipped at hi. So a question that asks many ramps from one speed (the
//! regula falsi of `max_speed`, the peak of a block) builds F once ([`Rise::from`]) and only B
//! and the merge per ramp; every piece, hence every sum, is the one a rise built whole gives.

use crate::feed::bands::{Banded, MAX_BANDS};
use crate::feed::{greater, lesser};
use arrayvec::ArrayVec;
use std::cell::RefCell;

/// Pieces at most in an envelope: a rise and a plateau per band.
const MAX_PIECES: usize = 2 * (MAX_BANDS + 1);

/// a² = alpha + beta·v on [v0, v1] (beta = 2·jerk; 0 on a plateau).
#[derive(Clone, Copy, Debug)]
pub(super) struct Piece {
    pub v0: f64,
    pub v1: f64,
    alpha: f64,
    beta: f64,
}

impl Piece {
    fn a2(&self, v: f64) -> f64 {
        (self.alpha + self.beta * v).max(0.0)
    }

    /// Duration, jerk and starting acceleration of the piece run as a phase.
    fn phase(&self) -> (f64, f64, f64) {
        let (a0, a1) = (self.a2(self.v0).sqrt(), self.a2(self.v1).sqrt());
        if self.beta == 0.0 {
            let a = a0.max(f64::MIN_POSITIVE);
            ((self.v1 - self.v0) / a, 0.0, a0)
        } else {
            let j = 0.5 * self.beta;
            (((a1 - a0) / j).max(0.0), j, a0)
        }
    }

    /// Duration, jerk and distance of the piece run as a phase (`phase`).
    pub fn run(&self) -> (f64, f64, f64) {
        let (tau, j, a0) = self.phase();
        (tau, j, tau * (self.v0 + tau * (0.5 * a0 + tau * j / 6.0)))
    }
}

/// A fixed-capacity list of pieces, by increasing speed (or decreasing, as built); never
/// zeroed (many are built, few pieces each).
#[derive(Clone, Debug, Default)]
struct Pieces(ArrayVec<Piece, MAX_PIECES>);

impl Pieces {
    fn push(&mut self, piece: Piece) {
        debug_assert!(!self.0.is_full(), "room for every piece");
        // Never full (a rise and a plateau per level): one capacity check, no panic path.
        if piece.v1 > piece.v0 {
            let _ = self.0.try_push(piece);
        }
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn as_slice(&self) -> &[Piece] {
        &self.0
    }
}

/// The bands of a ramp (`Level`), at most one per band and the block's top.
type Levels = ArrayVec<Level, { MAX_BANDS + 1 }>;
/// Per level, the index of its first piece of F (`forward_into`).
type Starts = ArrayVec<usize, { MAX_BANDS + 1 }>;

/// A band of the ramp: speeds [floor, top] with acceleration `a` and jerk `j`; the floor is
/// clipped to lo, the top is the band's own (∞ for the block's top band).
#[derive(Clone, Copy, Debug)]
struct Level {
    floor: f64,
    top: f64,
    a: f64,
    j: f64,
}

/// The bands crossed between `lo` and `hi` into `out` (empty), floors clipped to lo (tops are
/// not: see `Level`).
fn levels_into(b: &Banded, lo: f64, hi: f64, out: &mut Levels) {
    // Band k as `Banded::limits`, `floor_of` and `top_of` give it, read in one walk: the band
    // levels, then the block's own limits above them (no top). The bands (by increasing speed)
    // whose tops are at or below lo are passed over: none is taken (lo is their floor or above).
    let levels = b.bands.levels();
    let first = levels.partition_point(|l| l.v_top <= lo);
    let bands = levels[first..].iter().map(|l| (l.v_top, l.a_max, l.j_max));
    let mut floor_k: f64 = first.checked_sub(1).map_or(0.0, |k| levels[k].v_top);
    for (top_k, a, j) in bands.chain(std::iter::once((f64::INFINITY, b.top.a_max, b.top.j_max))) {
        let floor = greater(lo, floor_k);
        if lesser(hi, top_k) > floor {
            let _ = out.try_push(Level {
                floor,
                top: top_k,
                a,
                j,
            });
        }
        if top_k >= hi {
            break;
        }
        floor_k = top_k;
    }
}

/// Forward envelope over `levels`: a² grows by 2·J per unit of speed up to each band's A (cut
/// to it at the band's floor where the band below allowed more). Unclipped at the top. Into
/// `fwd` (empty), with the index of each level's first piece in `starts` (those of the levels
/// below come first).
fn forward_into(levels: &[Level], fwd: &mut Pieces, starts: &mut Starts) {
    let mut f: f64 = 0.0;
    for l in levels {
        starts.push(fwd.len());
        f = lesser(f, l.a);
        let reach = l.floor + (l.a * l.a - f * f) / (2.0 * l.j);
        let end = lesser(reach, l.top);
        fwd.push(Piece {
            v0: l.floor,
            v1: end,
            alpha: f * f - 2.0 * l.j * l.floor,
            beta: 2.0 * l.j,
        });
        if end < l.top {
            fwd.push(Piece {
                v0: end,
                v1: l.top,
                alpha: l.a * l.a,
                beta: 0.0,
            });
            f = l.a;
        } else {
            f = (f * f + 2.0 * l.j * (l.top - l.floor)).sqrt();
        }
    }
}

/// The backward envelope over `levels` from `hi` down (pieces by decreasing speed), where it has
/// acceleration `g` (0 at the end of a rise), into `bwd` (empty). With `to_plateau`, down to the
/// highest level k ≥ 1 where it comes onto that level's plateau: below k's floor it is then the
/// same whatever `hi` (it leaves k at acceleration A_k); returns k (0 where it went down through
/// every level).
// Inlined where it is called: once per distance a root search evaluates (`Rise::time_distance`).
#[inline(always)]
fn backward_from(levels: &[Level], hi: f64, mut g: f64, bwd: &mut Pieces, to_plateau: bool) -> usize {
    for (k, l) in levels.iter().enumerate().rev() {
        let top = lesser(hi, l.top);
        let g0 = lesser(g, l.a);
        let reach = top - (l.a * l.a - g0 * g0) / (2.0 * l.j);
        let start = greater(reach, l.floor);
        bwd.push(Piece {
            v0: start,
            v1: top,
            alpha: g0 * g0 + 2.0 * l.j * top,
            beta: -2.0 * l.j,
        });
        if start > l.floor {
            bwd.push(Piece {
                v0: l.floor,
                v1: start,
                alpha: l.a * l.a,
                beta: 0.0,
            });
            g = l.a;
            if to_plateau && k > 0 {
                return k;
            }
        } else {
            g = (g0 * g0 + 2.0 * l.j * (top - l.floor)).sqrt();
        }
    }
    0
}

/// min(F, B) up to `hi` over the common refinement of both: on each stretch both are a² linear
/// in v, so the smaller is the one below at its ends, the stretch split where they cross.
fn merge(fwd: &[Piece], bwd: &[Piece], hi: f64, mut take: impl FnMut(&Piece)) {
    // B from its lowest piece up; each step moves on past the piece (or both) that ends first.
    let (mut fs, mut bs) = (fwd.iter(), bwd.iter().rev());
    let (Some(mut f), Some(mut b)) = (fs.next(), bs.next()) else {
        return;
    };
    while f.v0 < hi {
        let f1 = lesser(f.v1, hi);
        let (u0, u1) = (greater(f.v0, b.v0), lesser(f1, b.v1));
        if u1 > u0 {
            let d = |u: f64| (f.alpha - b.alpha) + (f.beta - b.beta) * u;
            let (d0, d1) = (d(u0), d(u1));
            let piece = |x0: f64, x1: f64, forward: bool| Piece {
                v0: x0,
                v1: x1,
                ..*(if forward { f } else { b })
            };
            if (d0 <= 0.0) == (d1 <= 0.0) {
                take(&piece(u0, u1, d0 + d1 <= 0.0));
            } else {
                let root = (u0 - d0 * (u1 - u0) / (d1 - d0)).clamp(u0, u1);
                take(&piece(u0, root, d0 <= 0.0));
                take(&piece(root, u1, d1 <= 0.0));
            }
        }
        // Past the piece that ends first, or both where they end together (the next F piece
        // starts at or above b's end, so the step after would take nothing and go on past b).
        // At least one moves on, whatever the comparison gives.
        let f_ends = f1 <= b.v1;
        let b_ends = !f_ends || f1 == b.v1;
        if f_ends {
            let Some(next) = fs.next() else { return };
            f = next;
        }
        if b_ends {
            let Some(next) = bs.next() else { return };
            b = next;
        }
    }
}

/// Rises from one speed `lo` to any speed above it: F built once, up to the block's top band.
pub struct Rise<'a> {
    b: &'a Banded<'a>,
    lo: f64,
    /// The bands above lo (`levels` up to no top): those of a rise to hi are the ones below it.
    levels: Levels,
    fwd: Pieces,
    /// Index of each level's first piece of F.
    starts: Starts,
    /// Time and distance of the rise below level k's floor, for the rises whose B comes onto
    /// k's plateau (`backward_from`): the same pieces in the same order for all of them, so the
    /// sums go on from there bit for bit. Summed when first needed.
    below: RefCell<ArrayVec<Option<(f64, f64)>, { MAX_BANDS + 1 }>>,
}

impl<'a> Rise<'a> {
    /// The rises from `lo`, by value (a copy of a few kB: hot callers use `build_in`).
    pub fn from(b: &'a Banded<'a>, lo: f64) -> Rise<'a> {
        let mut slot = None;
        Rise::build_in(&mut slot, b, lo);
        slot.expect("built")
    }

    /// `from`, built in `slot` (a few kB, filled where it stays: a rise returned by value is
    /// copied whole). Its lists are never zeroed (many are built, one per start speed asked).
    #[inline(always)]
    pub fn build_in<'s>(slot: &'s mut Option<Rise<'a>>, b: &'a Banded<'a>, lo: f64) -> &'s Rise<'a> {
        let rise = slot.insert(Rise {
            b,
            lo,
            levels: Levels::new(),
            fwd: Pieces::default(),
            starts: Starts::new(),
            below: RefCell::new(ArrayVec::new()),
        });
        levels_into(b, lo, f64::INFINITY, &mut rise.levels);
        forward_into(&rise.levels, &mut rise.fwd, &mut rise.starts);
        rise.below.get_mut().extend(rise.levels.iter().map(|_| None));
        rise
    }

    pub fn lo(&self) -> f64 {
        self.lo
    }

    /// The band the rise starts in: its top speed (∞ for the block's top band) and limits.
    pub fn first_band(&self) -> Option<(f64, f64, f64)> {
        self.levels.first().map(|l| (l.top, l.a, l.j))
    }

    pub fn banded(&self) -> &'a Banded<'a> {
        self.b
    }

    /// Time and distance of the rise lo → hi (0 for hi ≤ lo): B down to its highest plateau,
    /// the merge above that level's floor, the sums below it kept (`below`).
    pub fn time_distance(&self, hi: f64) -> (f64, f64) {
        let mut sum = Sum::default();
        if hi > self.lo {
            let n = self.levels.partition_point(|l| l.floor < hi);
            let mut bwd = Pieces::default();
            let k = backward_from(&self.levels[..n], hi, 0.0, &mut bwd, true);
            if k > 0 {
                (sum.t, sum.s) = self.below(k);
            }
            let fwd = &self.fwd.as_slice()[self.starts[k]..];
            merge(fwd, bwd.as_slice(), hi, |p| sum.add(p));
        }
        (sum.t, sum.s)
    }

    /// The pieces of the rise lo → hi, in order, to `take`: those `rise` gives, from the kept F
    /// (the levels of a rise to hi are the ones below hi, and F on them is theirs).
    pub(super) fn pieces(&self, hi: f64, take: impl FnMut(&Piece)) {
        let n = self.levels.partition_point(|l| l.floor < hi);
        let mut bwd = Pieces::default();
        backward_from(&self.levels[..n], hi, 0.0, &mut bwd, false);
        let end = self.starts.get(n).copied().unwrap_or(self.fwd.len());
        merge(&self.fwd.as_slice()[..end], bwd.as_slice(), hi, take);
    }

    /// The sums of the rise below level k's floor with B leaving k at A_k (`below`). That B
    /// comes onto a plateau at a level j < k too, below which it is j's: the sums kept for j go
    /// on from there, as in `time_distance` (a search that moves across levels sums each once).
    fn below(&self, k: usize) -> (f64, f64) {
        if let Some(sums) = self.below.borrow()[k] {
            return sums;
        }
        let (floor, mut bwd) = (self.levels[k].floor, Pieces::default());
        let j = backward_from(&self.levels[..k], floor, self.levels[k].a, &mut bwd, true);
        let mut sum = Sum::default();
        if j > 0 {
            (sum.t, sum.s) = self.below(j);
        }
        let fwd = &self.fwd.as_slice()[self.starts[j]..self.starts[k]];
        merge(fwd, bwd.as_slice(), floor, |p| sum.add(p));
        self.below.borrow_mut()[k] = Some((sum.t, sum.s));
        (sum.t, sum.s)
    }
}

/// The band of the speeds just below `v` (floor < v ≤ top, the first band for 0), where a ramp
/// that ends at v from below runs last: its floor, acceleration and jerk.
pub fn band_below(b: &Banded, v: f64) -> (f64, f64, f64) {
    let mut floor = 0.0;
    for l in b.bands.levels() {
        if v <= l.v_top {
            return (floor, l.a_max, l.j_max);
        }
        floor = l.v_top;
    }
    (floor, b.top.a_max, b.top.j_max)
}

/// The speed rise lo → hi as constant-jerk pieces, in order, to `take` (F built for this rise only).
pub(super) fn rise(b: &Banded, lo: f64, hi: f64, take: impl FnMut(&Piece)) {
    let mut levels = Levels::new();
    levels_into(b, lo, hi, &mut levels);
    let (mut fwd, mut bwd) = (Pieces::default(), Pieces::default());
    forward_into(&levels, &mut fwd, &mut Starts::new());
    backward_from(&levels, hi, 0.0, &mut bwd, false);
    merge(fwd.as_slice(), bwd.as_slice(), hi, take);
}

/// Time and distance of the rise lo → hi (the drop hi → lo takes the same).
pub(super) fn rise_time_distance(b: &Banded, lo: f64, hi: f64) -> (f64, f64) {
    let mut sum = Sum::default();
    if hi > lo {
        rise(b, lo, hi, |p| sum.add(p));
    }
    (sum.t, sum.s)
}

/// Time and distance summed over pieces in order.
#[derive(Default)]
struct Sum {
    t: f64,
    s: f64,
}

impl Sum {
    fn add(&mut self, p: &Piece) {
        let (tau, _, ds) = p.run();
        self.t += tau;
        self.s += ds;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::bands::{Band, Bands};
    use crate::feed::{Limits, ProfileKind};
    use crate::test_rng::unit;

    /// A rise from a kept forward envelope (`Rise`) is the rise built whole, bit for bit (its
    /// sums and its pieces), on 200 random band sets (acceleration and jerk rising and falling
    /// with speed) for ramps within a band, across many, from rest, to band edges exactly and
    /// above the block's top speed.
    #[test]
    fn kept_forward_envelope_gives_the_same_rise() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200 {
            let top = Limits {
                v_max: 0.1 + 0.3 * unit(&mut s),
                a_max: 0.2 + 2.0 * unit(&mut s),
                j_max: 5.0 + 500.0 * unit(&mut s),
                snap_max: 1e9,
            };
            let levels: Vec<Band> = (0..16)
                .map(|_| Band {
                    v_top: top.v_max * unit(&mut s),
                    a_max: 0.2 + 3.0 * unit(&mut s),
                    j_max: 5.0 + 500.0 * unit(&mut s),
                })
                .collect();
            let bands = Bands::below(&top, &levels);
            let b = Banded {
                kind: ProfileKind::Scurve7,
                top: &top,
                bands: &bands,
            };
            let edges: Vec<f64> = bands.levels().iter().map(|l| l.v_top).collect();
            let mut speeds = vec![0.0, top.v_max, 1.5 * top.v_max];
            speeds.extend(&edges);
            speeds.extend((0..12).map(|_| top.v_max * unit(&mut s)));
            for &lo in &speeds {
                let rise = Rise::from(&b, lo);
                for &hi in &speeds {
                    let kept = rise.time_distance(hi);
                    let whole = rise_time_distance(&b, lo, hi);
                    assert_eq!(
                        [kept.0.to_bits(), kept.1.to_bits()],
                        [whole.0.to_bits(), whole.1.to_bits()],
                        "{lo} → {hi}: {kept:?} vs {whole:?}"
                    );
                    let bits = |p: &Piece| [p.v0, p.v1, p.alpha, p.beta].map(f64::to_bits);
                    let (mut kept, mut whole) = (Vec::new(), Vec::new());
                    rise.pieces(hi, |p| kept.push(bits(p)));
                    super::rise(&b, lo, hi, |p| whole.push(bits(p)));
                    assert_eq!(kept, whole, "{lo} → {hi}: pieces");
                }
            }
        }
    }
}

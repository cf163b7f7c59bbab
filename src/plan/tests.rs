//! The look-ahead planner on hand-made blocks: speeds through a chain and a stop at its end,
//! the lazily solved stop limits against the eager ones, the junction limit.

use super::*;
use crate::config::Machine;
use crate::feed::max_entry;
use crate::geometry::Line;
use crate::path::line_limits;

fn line_block(from: f64, to: f64, feed: f64, v_end_max: f64) -> PathBlock {
    let machine = Machine::default();
    let line = Line {
        start: [from, 0.0, 0.0],
        end: [to, 0.0, 0.0],
    };
    let limits = line_limits(line.direction(), &machine);
    PathBlock {
        line: 1,
        segment: Segment::Line(line),
        v_feed: feed.min(limits.v_max),
        limits,
        v_end_max,
        constant_speed: false,
        before_transition: false,
        bands: Default::default(),
    }
}

fn plan_all(kind: ProfileKind, blocks: &[PathBlock], window: usize) -> Vec<Planned> {
    let mut planner = Planner::new(kind, window);
    let mut out = VecDeque::new();
    for b in blocks {
        planner.push(b.clone(), &mut out);
    }
    planner.finish(&mut out);
    out.into_iter().collect()
}

#[test]
fn speeds_chain_and_stop_at_end() {
    for kind in ProfileKind::ALL {
        let blocks: Vec<_> = (0..50)
            .map(|i| line_block(i as f64 * 1e-3, (i + 1) as f64 * 1e-3, 0.05, 1.0))
            .collect();
        for window in [2, 7, 256] {
            let planned = plan_all(kind, &blocks, window);
            assert_eq!(planned.len(), 50);
            assert_eq!(planned[0].v_in, 0.0);
            assert!(
                planned.last().unwrap().v_out.abs() < 1e-9,
                "{kind:?} must stop at the end"
            );
            for w in planned.windows(2) {
                assert_eq!(w[0].v_out, w[1].v_in);
            }
            for p in &planned {
                assert!((p.profile.length() - 1e-3).abs() < 1e-12, "{kind:?}: length kept");
                assert!(p.v_in <= 0.05 + 1e-12 && p.v_out <= 0.05 + 1e-12);
            }
        }
    }
}

/// The stop limits computed when needed plan the same speeds, bit for bit, as all of them
/// computed when the segments come in (as before issue 22): every law, over stops, short
/// and long segments, two window sizes.
#[test]
fn lazy_stop_limits_plan_the_same() {
    let mut x: u64 = 7;
    let mut unit = move || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut at = 0.0;
    // Short blocks at speed, junction limits anywhere below the feed: slowing to a third
    // of a speed takes longer than stopping, so the stop limit decides many entries.
    let blocks: Vec<PathBlock> = (0..2000)
        .map(|_| {
            let length = 2e-5 * 50.0f64.powf(unit());
            let feed = 0.02 + 0.18 * unit();
            let v_end_max = if unit() < 0.05 { 0.0 } else { feed * unit() };
            at += length;
            line_block(at - length, at, feed, v_end_max)
        })
        .collect();
    for (kind, window) in ProfileKind::ALL.into_iter().flat_map(|k| [(k, 7), (k, 32)]) {
        let lazy = plan_all(kind, &blocks, window);
        let mut planner = Planner::new(kind, window);
        let mut out = VecDeque::new();
        for b in &blocks {
            planner.admit(b.clone());
            let e = planner.window.back_mut().unwrap();
            assert!(e.v_in_stop.is_nan(), "not computed on admission");
            e.v_in_stop = max_entry(kind, e.block.segment.length(), 0.0, &e.block.limits);
            planner.release(&mut out);
        }
        planner.finish(&mut out);
        assert_eq!(out.len(), lazy.len());
        for (eager, lazy) in out.iter().zip(&lazy) {
            assert_eq!((eager.v_in, eager.v_out), (lazy.v_in, lazy.v_out), "{kind:?}");
            assert_eq!(eager.profile, lazy.profile);
        }
    }
}

/// One entry's limit, lazy against eager, over exits and caps where the stop decides
/// (slowing to a third of a speed takes longer than stopping: seed 004's ramp distance is
/// not monotone in the exit) and where it does not.
#[test]
fn lazy_stop_limit_of_one_entry() {
    let mut decided_by_stop = 0;
    for kind in ProfileKind::ALL {
        for length in [2e-5, 1e-4, 5e-4, 2e-3] {
            let block = line_block(0.0, length, 0.2, 1.0);
            let stop = max_entry(kind, length, 0.0, &block.limits);
            for i in 0..=40 {
                let v_exit = stop * i as f64 / 40.0;
                for cap in [0.5 * stop, stop, 2.0 * stop, 0.2] {
                    let mut e = Entry {
                        block: block.clone(),
                        v_in_cap: cap,
                        v_in_lim: f64::NAN,
                        v_in_pass: f64::NAN,
                        v_in_stop: f64::NAN,
                        v_feed: 0.2,
                    };
                    let slow = max_entry(kind, length, v_exit, &block.limits);
                    let eager = if cap <= v_exit {
                        cap.min(v_exit)
                    } else {
                        cap.min(slow.max(stop))
                    };
                    let lazy = entry_limit(kind, &mut e, v_exit, true).0;
                    assert_eq!(
                        lazy.to_bits(),
                        eager.to_bits(),
                        "{kind:?} {length} {v_exit} {cap}"
                    );
                    if cap > v_exit && stop > slow && cap > slow {
                        decided_by_stop += 1;
                    }
                }
            }
        }
    }
    assert!(
        decided_by_stop > 0,
        "the stop limit never decided: the test tests nothing"
    );
}

#[test]
fn junction_limit_is_respected() {
    let mut blocks: Vec<_> = (0..4)
        .map(|i| line_block(i as f64 * 0.01, (i + 1) as f64 * 0.01, 0.1, 1.0))
        .collect();
    blocks[1].v_end_max = 0.0;
    let planned = plan_all(ProfileKind::Scurve7, &blocks, 256);
    assert_eq!(planned[1].v_out, 0.0);
    assert_eq!(planned[2].v_in, 0.0);
}

/// `rest_ramp_floor` is a floor of the joined bands' ramp from rest as evaluated (200 random
/// band sets, speeds across and above them): `stop_is_below` answers the same with it.
#[test]
fn rest_ramp_floor_is_below_the_ramp() {
    use crate::feed::bands::{Band, Bands};
    use crate::feed::Limits;
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..200 {
        let top = Limits {
            v_max: 0.01 + 0.2 * uniform(),
            a_max: 0.5 + 3.0 * uniform(),
            j_max: 10.0 + 200.0 * uniform(),
            snap_max: f64::INFINITY,
        };
        let (mut a, mut j) = (top.a_max, top.j_max);
        let mut levels = Vec::new();
        for k in (1..=4).rev() {
            (a, j) = (a * (1.0 + uniform()), j * (1.0 + 2.0 * uniform()));
            let v_top = top.v_max * f64::from(k) / 5.0 * (0.8 + 0.2 * uniform());
            levels.push(Band {
                v_top,
                a_max: a,
                j_max: j,
            });
        }
        levels.reverse();
        let bands = Bands::below(&top, &levels);
        let banded = Banded {
            kind: ProfileKind::Scurve7,
            top: &top,
            bands: &bands,
        };
        assert!(banded.joined());
        for i in 1..=40 {
            let v = top.v_max * 1.2 * f64::from(i) / 40.0;
            let d = scurve7_banded::ramp_distance(&banded, 0.0, v);
            let floor = rest_ramp_floor(&banded, v);
            assert!(floor <= d * (1.0 + 1e-12), "v {v}: floor {floor} > ramp {d}");
        }
    }
}

//! Time in whole ticks, through the C ABI as importers step: masters that form t and h in their
//! own floating point get the same outputs bit for bit, and at h = T every interpolation tick is
//! seen once, none twice, none skipped, for a minute of motion.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

#[macro_use]
mod common;

use common::*;

const T: f64 = 1e-3;
/// A straight line that takes a minute at 70 mm/min (plus its ramps), on three axes.
const LINE: &str = "G21 G90 G1 X70 Y35 Z-7 F78.615\nM30\n";

/// How a master forms its communication points and step sizes, step n → n + 1.
#[derive(Clone, Copy, Debug)]
enum Master {
    /// t = n·h, h = T (fmpy).
    Product,
    /// h = (n + 1)·T − n·T (a master that steps between time points it computed).
    Difference,
    /// t += h (Ecos).
    Sum,
    /// Integer nanoseconds: t = n_ns·1e-9 (libcosim).
    Nanoseconds,
}

impl Master {
    const ALL: [Master; 4] = [
        Master::Product,
        Master::Difference,
        Master::Sum,
        Master::Nanoseconds,
    ];

    /// (t, h) of step n, given the t the previous step ended at (for the sum).
    fn step(self, n: u64, t_sum: f64) -> (f64, f64) {
        let at = |n: u64| n as f64 * T;
        match self {
            Master::Product => (at(n), T),
            Master::Difference => (at(n), at(n + 1) - at(n)),
            Master::Sum => (t_sum, T),
            Master::Nanoseconds => {
                let ns = |n: u64| (n * 1_000_000) as f64 * 1e-9;
                (ns(n), ns(n + 1) - ns(n))
            }
        }
    }
}

/// One instance per master, servo on, stepped together for `steps`; `each(n, outputs)` sees
/// the outputs (all masters' equal, or the test fails) after step n.
fn side_by_side(fmu: &Fmu, masters: &[Master], program: &str, steps: u64, mut each: impl FnMut(u64, &[f64])) {
    let instances: Vec<_> = masters
        .iter()
        .map(|m| {
            let c = fmu.instantiate(&format!("{m:?}"));
            assert_eq!(fmu.init(c, Some(program)), OK);
            c
        })
        .collect();
    let mut t_sum = vec![0.0; masters.len()];
    for n in 0..steps {
        let mut first: Option<Vec<f64>> = None;
        for (k, (&c, &master)) in instances.iter().zip(masters).enumerate() {
            let (t, h) = master.step(n, t_sum[k]);
            assert_eq!(fmu.step(c, t, h), OK, "{master:?} at step {n}");
            t_sum[k] = t + h;
            let out = fmu.outputs(c);
            match &first {
                None => first = Some(out),
                Some(f) => {
                    for (i, (a, b)) in f.iter().zip(&out).enumerate() {
                        assert!(
                            a.to_bits() == b.to_bits(),
                            "step {n}: {} = {a:e} ({:?}) but {b:e} ({master:?})",
                            fmu.outputs[i].0,
                            masters[0]
                        );
                    }
                }
            }
        }
        each(n, first.as_deref().unwrap());
    }
    for c in instances {
        fmu.free(c);
    }
}

#[test]
fn importers_forming_h_differently_get_identical_outputs() {
    let fmu = Fmu::load();
    let text = include_str!("../resources/default.ngc");
    // The default program and two seconds at rest, servo on: all 34 outputs, bit for bit.
    let finished = fmu.outputs.iter().position(|o| o.0 == "status.finished").unwrap();
    let mut done = false;
    side_by_side(&fmu, &Master::ALL, text, 8000, |_, out| {
        done = out[finished] == 1.0
    });
    assert!(done, "the program ran to its end");
}

#[test]
fn every_tick_is_seen_once_at_h_equal_to_the_period() {
    let fmu = Fmu::load();
    let names: Vec<&str> = fmu.outputs.iter().map(|o| o.0.as_str()).collect();
    let at = |name: &str| names.iter().position(|n| *n == name).unwrap();
    let (x, vx, finished) = (
        at("x.command.position"),
        at("x.command.velocity"),
        at("status.finished"),
    );
    // The engine's own ticks, as the CLI steps them (t = (n + 1)·T).
    let machine = cnc_motion::config::Machine::default();
    let mut engine = cnc_motion::engine::Engine::new(LINE, "program", &machine).unwrap();
    let mut moving_steps = 0;
    let mut last = (0.0f64, 0.0f64);
    // Before whole ticks, masters forming t as n·T or as a sum of h lost tick 11620 (11.62/0.001
    // is 11619.999999999998 in binary): the outputs repeated tick 11619, the next step advanced two.
    let masters = [Master::Product, Master::Difference];
    side_by_side(&fmu, &masters, LINE, 61_000, |n, out| {
        let tick = *engine.step().unwrap();
        // The tick the engine emits at (n + 1)·T is the one every master sees after step n.
        assert_eq!(
            out[x].to_bits(),
            tick.p[0].to_bits(),
            "tick {} missing or repeated",
            n + 1
        );
        assert_eq!(out[vx].to_bits(), tick.v[0].to_bits(), "tick {}", n + 1);
        // From the samples alone: moving, the position advances every step, by about v·T (a
        // repeated sample advances 0, a double step about 2·v·T).
        let (x_prev, v_prev) = last;
        if out[finished] == 0.0 && v_prev > 0.0 && out[vx] > 0.0 {
            let dx = out[x] - x_prev;
            let (slow, fast) = (v_prev.min(out[vx]), v_prev.max(out[vx]));
            assert!(
                dx > 0.5 * slow * T,
                "step {n}: x.command.position advanced {dx:e} m, v = {slow:e} m/s"
            );
            assert!(
                dx < 1.5 * fast * T,
                "step {n}: x.command.position advanced {dx:e} m, v = {fast:e} m/s"
            );
            moving_steps += 1;
        }
        last = (out[x], out[vx]);
    });
    assert!(engine.finished(), "the line takes a minute");
    assert!(moving_steps > 59_000, "{moving_steps} steps while moving");
}

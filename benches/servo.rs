//! ns per 1 ms interpolation period for three servo axes at the default 8 kHz servo rate.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use cnc_motion::servo::{AxisCommand, ServoAxis, ServoParams};
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let p = ServoParams::default();
    let mut axes: Vec<ServoAxis> = (0..3).map(|i| ServoAxis::new(p, i as f64 * 0.01)).collect();
    let mut t = 0.0f64;
    c.bench_function("servo/three_axes_1ms_at_8kHz", |b| {
        b.iter(|| {
            t += 1e-3;
            for (i, a) in axes.iter_mut().enumerate() {
                let cmd = AxisCommand {
                    position: 0.01 * (t + i as f64).sin(),
                    velocity: 0.01 * t.cos(),
                    acceleration: 0.0,
                };
                a.step(black_box(&cmd), 0.0, 1e-3);
            }
            axes[0].state().position
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);

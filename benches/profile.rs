//! PLACEHOLDER benchmark (profile): replaced by the module's real benchmark.
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    c.bench_function("profile/placeholder", |b| {
        b.iter(|| std::hint::black_box(1.0f64).sqrt())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);

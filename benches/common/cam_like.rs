//! A CAM-like program generator for throughput benchmarks (issue 22): what finishing toolpaths
//! of free-form parts look like as G-code. Random 0.05–2 mm G1 moves with small turns (now and
//! then a sharper one), a slowly wandering Z slope, some short G2/G3 arcs, coordinates in four
//! decimals, the feed changed now and then. On the default machine it runs about 35 ticks of
//! 1 ms per block, as real CAM programs do. Deterministic: the same `seed` gives the same text.

/// SplitMix64: small, fast and good enough to draw geometry from (no dependency).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// Feeds (mm/min) the program switches between, as CAM does for finishing passes.
const FEEDS: [f64; 4] = [2400.0, 3000.0, 3600.0, 4500.0];

/// Writes a program of `moves` motion lines (plus a header and M30) into `out`.
pub fn write(out: &mut impl std::fmt::Write, moves: usize, seed: u64) -> std::fmt::Result {
    let mut rng = Rng(seed);
    writeln!(out, "(CAM-like finishing path, {moves} moves, seed {seed})")?;
    writeln!(out, "G21 G90 G17 G64 P0.01")?;
    writeln!(out, "G0 X0 Y0 Z5")?;
    writeln!(out, "G1 Z0 F{}", FEEDS[1])?;
    let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64);
    let mut heading = 0.0f64;
    let mut slope = 0.0f64;
    for i in 0..moves {
        let length = rng.range(0.05, 2.0);
        let feed = (i % 500 == 499).then(|| FEEDS[(rng.next() % 4) as usize]);
        let f_word = feed.map(|f| format!(" F{f}")).unwrap_or_default();
        slope = (slope + rng.range(-0.05, 0.05)).clamp(-0.3, 0.3);
        let dz = slope * length;
        if rng.unit() < 0.1 {
            // A short arc tangent to the current heading, turning by length / radius.
            let radius = rng.range(2.0, 20.0);
            let sweep = (length / radius).min(1.0);
            let ccw = rng.unit() < 0.5;
            let side = if ccw { 1.0 } else { -1.0 };
            let normal = heading + side * std::f64::consts::FRAC_PI_2;
            let (cx, cy) = (x + radius * normal.cos(), y + radius * normal.sin());
            let start = normal + std::f64::consts::PI;
            let end = start + side * sweep;
            let (ex, ey) = (round4(cx + radius * end.cos()), round4(cy + radius * end.sin()));
            let (i_off, j_off) = (round4(cx - x), round4(cy - y));
            z = round4(z + dz);
            let code = if ccw { "G3" } else { "G2" };
            writeln!(
                out,
                "{code} X{ex:.4} Y{ey:.4} Z{z:.4} I{i_off:.4} J{j_off:.4}{f_word}"
            )?;
            heading += side * sweep;
            (x, y) = (ex, ey);
        } else {
            // Small turns, now and then a sharper one (a feature edge).
            let turn = if rng.unit() < 0.02 {
                rng.range(-0.8, 0.8)
            } else {
                rng.range(-0.02, 0.02)
            };
            heading += turn;
            x = round4(x + length * heading.cos());
            y = round4(y + length * heading.sin());
            z = round4(z + dz);
            writeln!(out, "G1 X{x:.4} Y{y:.4} Z{z:.4}{f_word}")?;
        }
        // Keep the part within ±50 mm: steer back towards the middle, 0.2 rad a move at most.
        if x.abs() > 50.0 || y.abs() > 50.0 {
            let back = (-y).atan2(-x) - heading;
            let back = back.sin().atan2(back.cos());
            heading += back.clamp(-0.2, 0.2);
        }
        if z.abs() > 10.0 {
            slope = -z.signum() * 0.1;
        }
    }
    writeln!(out, "M30")
}

/// The program as one string.
pub fn program(moves: usize, seed: u64) -> String {
    let mut text = String::with_capacity(moves * 36 + 128);
    write(&mut text, moves, seed).expect("writing to a String");
    text
}

fn round4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

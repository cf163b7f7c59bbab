//! Fuzz harness (issue 11): mutates the corpus programs (corpus/*.ngc,
//! resources/default.ngc), programs with issue 20's words (G10 L2 R, polar, G5.x, `%`, L
//! repeats, group-0 codes with motion; return from a nested `if`, G80 beside a motion code, F0,
//! G41/G42 entry arcs, G18/G19 arcs in a rotated system, a subroutine file through the machine
//! file's `subroutine_path`) and machine files, runs each case through the library with a bounded
//! number of ticks, and sorts the outcome:
//!
//! - `finished`: the programmed end reached exactly, every tick finite, no jump, axis velocity and
//!   acceleration within the machine's limits;
//! - `program error` / `machine error`: refused with `FILE:LINE:COL` inside the file;
//! - `not finished`: still running after the tick budget (stalls of the corner/plan stages are
//!   recorded here and do not fail the test for now);
//! - failures: panic, non-finite value, unlocated error, jump, limit exceeded, wrong end.
//!
//! Deterministic: CNC_FUZZ_SEED (default below, as `.ci/run` pins) and CNC_FUZZ_CASES (default
//! 5000); `make fuzz` runs a fresh seed with more cases. Prints the outcome table.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use cnc_motion::error::ProgramError;
use cnc_motion::gcode::{Motion, Reader};
use std::collections::BTreeMap;
use std::panic::{catch_unwind, AssertUnwindSafe};

const DEFAULT_SEED: u64 = 20_261_123;
const DEFAULT_CASES: usize = 5000;
/// Ticks per case before "not finished".
const MAX_TICKS: u64 = 20_000;
/// Relative slack on the limits (the engine's own property tests use 1e-9 on exact programs).
const REL: f64 = 1e-6;

/// xorshift64*: small, deterministic, good enough to pick mutations.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn corpus() -> Vec<(String, String)> {
    let mut out = vec![(
        "default.ngc".to_string(),
        include_str!("../resources/default.ngc").to_string(),
    )];
    // Cutter compensation (issue 14): seed 003's pocket with G41.1 D10.
    out.push((
        "seed003_pocket_g41.ngc".to_string(),
        include_str!("../examples/seed003_pocket_g41.ngc").to_string(),
    ));
    for (name, text) in LINUXCNC {
        out.push((name.to_string(), text.to_string()));
    }
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/corpus");
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("corpus beside the clone")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ngc"))
        .collect();
    paths.sort();
    for p in paths {
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        out.push((name, std::fs::read_to_string(&p).unwrap()));
    }
    out
}

/// Issue 20: programs with the words the reader runs as LinuxCNC does — G10 L2/L20 with R,
/// polar `@` `^` (also in a cycle), G5 / G5.1 / G5.2…G5.3, `%` demarcation, canned-cycle L
/// repeats in G90 and G91, group-0 codes (G4, G92, G53) with motion — mutated like the corpus.
const LINUXCNC: [(&str, &str); 6] = [
    (
        "samples.ngc",
        "G21 G90 G17 G40 G80 G00 X0 Y0 Z1\nF0\nF1000\no100 sub\no110 if [#1 GT 0]\no110 return [#1 * 2]\n\
         o110 endif\no100 endsub [1]\no100 call [3]\nG1 X#<_value> Y1\nG80 G1 X2\no<fuzz_sub> call [1]\n\
         G10 L2 P1 X1 Y1 R30\nG54 G0 X3 Y0 Z1\nG18 G2 X5 Z1 I1 K0\nG19 G3 Y2 Z1 R1\nG17 G0 Z1\nG10 L2 P1 X0 Y0 R0\n\
         G0 X-5 Y0\nG41.1 D2\nG3 X5 Y0 I5 J0\nG1 Y5\nG40 G0 X10 Y10\nM2\n",
    ),
    (
        "rotation.ngc",
        "G21 G90 G17 F1500\nG10 L2 P1 X10 Y5 R30\nG54 G1 X5 Y0\nG3 X0 Y5 I-5 J0\nG91 G1 X2 Y1\n\
         G90 G0 X0 Y0\nG10 L20 P1 X1 Y1\nG1 X3 Y2\nG92 X0 Y0\nG1 X1 Y-1\nG92.1\n\
         G10 L2 P1 X0 Y0 R0\nG53 G0 X0 Y0\nM2\n",
    ),
    (
        "polar.ngc",
        "G21 F1200\nG1 @5 ^30\nG91 ^45\n@1 ^45\nG90 G0 @2 ^0\nG0 Z5\nG81 @4 ^90 Z-1 R1 F300\nG80\nM2\n",
    ),
    (
        "splines.ngc",
        "G21 G17 G64 P0.01 F2000\nG0 X0 Y0\nG5 I0 J3 P0 Q-3 X1 Y1\nG5 P0 Q-3 X2 Y2\nG5.1 X4 Y2 I1 J2\n\
         G5.2 P1 L3\nX5 Y3 P1\nX6 Y1 P2\nX7 Y2 P1\nG5.3\nG0 X0 Y0\nM2\n",
    ),
    (
        "percent.ngc",
        "%\nG21 F1000\nG1 X2 Y1 G4 P0.05\nG1 X3 M1\nG4 P0.01 G0 X1\n%\nG1 X50\n",
    ),
    (
        "repeats.ngc",
        "G21 G0 Z5\nG81 X5 Y0 Z-1 R1 L2 F600\nG91 G81 X2 Y1 Z-1 R-3 L3\nG90 G80\nG0 Z5\n\
         G83 X1 Y1 Z-2 R1 Q0.5 L2\nG80\nG1 X1 Y1 F900 G4 P0.1\nM2\n",
    ),
];

const EXTREME: [&str; 12] = [
    "1e400",
    "-1e400",
    "2e157",
    "5e-324",
    "0",
    "-0",
    "1e-9",
    "100000",
    "100001",
    "999999999",
    "-3.5",
    "0.0001",
];
const NOISE: [&str; 29] = [
    "G",
    "X",
    "Y",
    "(",
    ")",
    "#",
    "[",
    ";",
    "%",
    " ",
    "\n",
    "G64 Q-1",
    "\u{feff}",
    "F",
    "@",
    "^",
    "G5.2 ",
    "G5.3\n",
    "L3 ",
    "G4 P0.1 ",
    "R90 ",
    "G10 L2 P1 R45\n",
    "%\n",
    "G80 ",
    "G18 ",
    "G41.1 D1 ",
    "o110 return\n",
    "o<fuzz_sub> call [2]\n",
    "O<fuzz_sub> callsub\n",
];

/// Start and end of every number in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i].is_ascii_digit() || (b[i] == b'-' && b.get(i + 1).is_some_and(u8::is_ascii_digit)) {
            let start = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.' || b[i] == b'e') {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// One mutation of the text: a number scaled, negated or replaced by an extreme value, a
/// character deleted, noise inserted, a line duplicated or dropped.
fn mutate(text: &mut String, rng: &mut Rng) {
    let nums = numbers(text);
    match rng.below(6) {
        0 | 1 if !nums.is_empty() => {
            let (a, b) = *rng.pick(&nums);
            let old: f64 = text[a..b].parse().unwrap_or(1.0);
            let new = match rng.below(3) {
                0 => rng.pick(&EXTREME).to_string(),
                1 => format!("{:.4}", old * (0.01 + 3.0 * rng.unit())),
                _ => format!("{}", -old),
            };
            text.replace_range(a..b, &new);
        }
        2 if !text.is_empty() => {
            let mut at = rng.below(text.len());
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            text.remove(at);
        }
        3 => {
            let mut at = rng.below(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            let noise = *rng.pick(&NOISE);
            text.insert_str(at, noise);
        }
        _ => {
            let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
            if lines.is_empty() {
                return;
            }
            let k = rng.below(lines.len());
            if rng.below(2) == 0 {
                lines.insert(k, lines[k]);
            } else {
                lines.remove(k);
            }
            *text = lines.concat();
        }
    }
}

/// The subroutine file the programs call (`o<fuzz_sub> call`): a directory of its own under
/// the temporary one, written once.
const FUZZ_SUB: &str =
    "o<fuzz_sub> sub\no1 repeat [#1]\nG91 G1 X0.5 Y0.25\no1 endrepeat\nG90\no<fuzz_sub> endsub [#1]\n";

fn sub_dir() -> &'static std::path::Path {
    static DIR: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("cnc_fuzz_subs_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("fuzz_sub.ngc"), FUZZ_SUB).unwrap();
        dir
    })
}

/// A machine file's text with `subroutine_path` naming the fuzz subroutine's directory.
fn with_subs(machine: &str) -> String {
    format!(
        "subroutine_path = [{:?}]\n{machine}",
        sub_dir().display().to_string()
    )
}

/// The machine file of a case: the corpus machine or an empty one (with the subroutine
/// directory), mutated a few times, or a key of the table set to an extreme value.
fn machine_text(rng: &mut Rng) -> String {
    let dmu = include_str!("../corpus/dmu50_840d.toml");
    let mut text = with_subs(if rng.below(2) == 0 { dmu } else { "" });
    if rng.below(4) == 0 {
        if rng.below(2) == 0 {
            mutate(&mut text, rng);
        } else {
            let keys = cnc_motion::config::ranges::MACHINE;
            let key = rng.pick(keys).key;
            text = format!("{key} = {}\n{text}", rng.pick(&EXTREME));
        }
    }
    text
}

#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Outcome {
    Finished,
    ProgramError,
    MachineError,
    NotFinished,
    Panic,
    NonFinite,
    Unlocated,
    Jump,
    LimitExceeded,
    WrongEnd,
}

impl Outcome {
    fn fails(self) -> bool {
        self > Outcome::NotFinished
    }
}

/// An error is located when its line is in the file (or one past the end) and its column in
/// that line (or one past its end); an error in the subroutine file is located in that file.
fn located(e: &ProgramError, text: &str, file: &str) -> bool {
    let sub = sub_dir().join("fuzz_sub.ngc").display().to_string();
    let (text, file) = if e.file == sub {
        (FUZZ_SUB, sub.as_str())
    } else {
        (text, file)
    };
    let lines: Vec<&str> = text.split('\n').collect();
    let line_ok = e.file == file && e.line >= 1 && (e.line as usize) <= lines.len() + 1;
    let width = lines.get(e.line as usize - 1).map_or(0, |l| l.len());
    line_ok && e.col >= 1 && (e.col as usize) <= width + 1
}

/// End of the last motion of the program, read as the engine reads it.
fn programmed_end(text: &str, machine: &Machine) -> Option<[f64; 3]> {
    let mut r = Reader::new(text, "p.ngc", [0.0; 3]).with_machine(machine);
    let mut end = [0.0; 3];
    while let Some(b) = r.next_block().ok()? {
        if let Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } = b.motion {
            end = to;
        }
    }
    Some(end)
}

fn run_case(program: &str, machine_toml: &str) -> (Outcome, String) {
    let machine = match Machine::from_toml(machine_toml, "m.toml") {
        Ok(m) => m,
        Err(e) if located(&e, machine_toml, "m.toml") => return (Outcome::MachineError, e.to_string()),
        Err(e) => return (Outcome::Unlocated, e.to_string()),
    };
    let mut engine = match Engine::new(program, "p.ngc", &machine) {
        Ok(e) => e,
        Err(e) if located(&e, program, "p.ngc") => return (Outcome::ProgramError, e.to_string()),
        Err(e) => return (Outcome::Unlocated, e.to_string()),
    };
    let period = machine.interpolation_period;
    let mut last = engine.tick().p;
    for _ in 0..MAX_TICKS {
        let tick = match engine.step() {
            Ok(t) => *t,
            Err(e) if located(&e, program, "p.ngc") => return (Outcome::ProgramError, e.to_string()),
            Err(e) => return (Outcome::Unlocated, e.to_string()),
        };
        let values = [tick.p, tick.v, tick.a, tick.j];
        if !values.iter().flatten().all(|x| x.is_finite()) || !tick.feed.is_finite() {
            return (Outcome::NonFinite, format!("{tick:?}"));
        }
        for (i, lim) in machine.axes.iter().enumerate() {
            let step = (tick.p[i] - last[i]).abs();
            if step > lim.max_velocity * period * (1.0 + REL) + 1e-12 {
                return (
                    Outcome::Jump,
                    format!("axis {i} moved {step} m in one tick at t = {}", tick.t),
                );
            }
            if tick.v[i].abs() > lim.max_velocity * (1.0 + REL)
                || tick.a[i].abs() > lim.max_acceleration * (1.0 + REL)
            {
                return (
                    Outcome::LimitExceeded,
                    format!(
                        "axis {i} v {} a {} at t = {} line {}",
                        tick.v[i], tick.a[i], tick.t, tick.line
                    ),
                );
            }
        }
        last = tick.p;
        if tick.finished {
            let want = programmed_end(program, &machine).unwrap_or(tick.p);
            let off = (0..3).map(|i| (tick.p[i] - want[i]).abs()).fold(0.0, f64::max);
            if off > 1e-9 {
                return (
                    Outcome::WrongEnd,
                    format!("ended {:?}, programmed {want:?}", tick.p),
                );
            }
            return (Outcome::Finished, String::new());
        }
    }
    (
        Outcome::NotFinished,
        format!("line {} at t = {}", engine.tick().line, engine.time()),
    )
}

#[test]
fn mutated_corpus_programs_and_machines() {
    let seed: u64 = env_or("CNC_FUZZ_SEED", DEFAULT_SEED);
    let cases: usize = env_or("CNC_FUZZ_CASES", DEFAULT_CASES);
    let programs = corpus();
    let mut rng = Rng(seed.max(1));
    let mut table: BTreeMap<Outcome, usize> = BTreeMap::new();
    let mut failures = Vec::new();
    let start = std::time::Instant::now();
    for case in 0..cases {
        let (name, base) = rng.pick(&programs).clone();
        let mut program = base;
        for _ in 0..1 + rng.below(3) {
            mutate(&mut program, &mut rng);
        }
        let machine = machine_text(&mut rng);
        let (outcome, detail) = catch_unwind(AssertUnwindSafe(|| run_case(&program, &machine)))
            .unwrap_or_else(|p| (Outcome::Panic, format!("{:?}", p.downcast_ref::<String>())));
        *table.entry(outcome).or_default() += 1;
        if outcome.fails() && failures.len() < 5 {
            failures.push(format!(
                "case {case} ({name}) {outcome:?}: {detail}\n--- program\n{program}\n--- machine\n{machine}"
            ));
        }
    }
    eprintln!(
        "fuzz: seed {seed}, {cases} cases in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    for (outcome, n) in &table {
        eprintln!("  {:<16} {n:>6}", format!("{outcome:?}"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn harness_classifies_known_cases() {
    let dmu = with_subs(include_str!("../corpus/dmu50_840d.toml"));
    for (_, text) in corpus() {
        let (outcome, detail) = run_case(&text, &dmu);
        assert_eq!(outcome, Outcome::Finished, "{text}\n{detail}");
    }
    let ok = "G21 G1 X1 F100\n";
    assert_eq!(
        run_case(ok, "lookahead_blocks = 100000000\n").0,
        Outcome::MachineError
    );
    assert_eq!(
        run_case("G21 F100\nG1 X#<undefined>\n", "").0,
        Outcome::ProgramError
    );
    // An error outside the file is unlocated.
    let far = ProgramError::new("p.ngc", 1, 99, "x");
    assert!(!located(&far, ok, "p.ngc") && located(&ProgramError::new("p.ngc", 2, 1, "x"), ok, "p.ngc"));
    assert_eq!(run_case(ok, "").0, Outcome::Finished);
}

//! `cnc-motion run`: a whole program through the engine, tick by tick; summary, CSV, progress.

use crate::summary;
use clap::Args;
use cnc_motion::config::Machine;
use cnc_motion::engine::{Engine, Outputs};
use cnc_motion::gcode::ProgramSource;
use cnc_motion::interp::{Differences, Tick};
use cnc_motion::path::Segment;
use cnc_motion::servo::AxisState;
use cnc_motion::Vec3;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use cnc_motion::si::MM;

#[derive(Args)]
pub struct RunArgs {
    /// G-code program file.
    program: String,
    /// Machine file (TOML); defaults when absent.
    #[arg(long)]
    machine: Option<String>,
    /// Write every tick to this CSV file.
    #[arg(long)]
    csv: Option<String>,
    /// Simulate the servo-axis drives too.
    #[arg(long)]
    servo: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    json: bool,
    /// Stop after this many seconds of simulated time even if the program is not done.
    #[arg(long, default_value_t = 86_400.0)]
    max_time: f64,
}

/// One line of `--csv` (mm, s); the field names are the header. Numbers are written in their
/// shortest round-trip form (`0.0`, `1e-7`).
#[derive(Serialize)]
struct CsvRow {
    time_s: f64,
    line: u32,
    x_mm: f64,
    y_mm: f64,
    z_mm: f64,
    feed_mm_s: f64,
    vx_mm_s: f64,
    vy_mm_s: f64,
    vz_mm_s: f64,
    ax_mm_s2: f64,
    ay_mm_s2: f64,
    az_mm_s2: f64,
    jx_mm_s3: f64,
    jy_mm_s3: f64,
    jz_mm_s3: f64,
    x_act_mm: f64,
    y_act_mm: f64,
    z_act_mm: f64,
}

impl CsvRow {
    fn new(tick: &Tick, axes: &[AxisState; 3]) -> CsvRow {
        let [x_mm, y_mm, z_mm] = tick.p.map(|x| x / MM);
        let [vx_mm_s, vy_mm_s, vz_mm_s] = tick.v.map(|x| x / MM);
        let [ax_mm_s2, ay_mm_s2, az_mm_s2] = tick.a.map(|x| x / MM);
        let [jx_mm_s3, jy_mm_s3, jz_mm_s3] = tick.j.map(|x| x / MM);
        let [x_act_mm, y_act_mm, z_act_mm] = axes.map(|s| s.position / MM);
        CsvRow {
            time_s: tick.t,
            line: tick.line,
            x_mm,
            y_mm,
            z_mm,
            feed_mm_s: tick.feed / MM,
            vx_mm_s,
            vy_mm_s,
            vz_mm_s,
            ax_mm_s2,
            ay_mm_s2,
            az_mm_s2,
            jx_mm_s3,
            jy_mm_s3,
            jz_mm_s3,
            x_act_mm,
            y_act_mm,
            z_act_mm,
        }
    }
}

/// Running maxima of |x| per axis.
#[derive(Default)]
struct Peaks([f64; 3]);

impl Peaks {
    fn take(&mut self, x: [f64; 3]) {
        for (m, v) in self.0.iter_mut().zip(x) {
            // `f64::max` as one compare: a NaN is passed over either way, and the peak, never
            // NaN, is the same.
            let v = v.abs();
            *m = if v > *m { v } else { *m };
        }
    }
    fn mm(&self) -> [f64; 3] {
        self.0.map(|v| v / MM)
    }
}

/// What the summary reports of the whole run: per axis the larger of the feed law's values and
/// what the emitted ticks show (finite differences from rest catch steps at corners).
#[derive(Default)]
struct Maxima {
    v: Peaks,
    a: Peaks,
    j: Peaks,
    /// The largest |position| per axis: the finite differences' rounding floor scales with it.
    extent: Peaks,
    following_error: Peaks,
    torque: Peaks,
    contour: f64,
    ticks: u64,
}

impl Maxima {
    /// The command's maxima, from the tick and its finite differences.
    fn take(&mut self, tick: &Tick, emitted: (Vec3, Vec3, Vec3)) {
        let (dv, da, dj) = emitted;
        for (peaks, law, shown) in [
            (&mut self.v, tick.v, dv),
            (&mut self.a, tick.a, da),
            (&mut self.j, tick.j, dj),
        ] {
            peaks.take(law);
            peaks.take(shown);
        }
        self.extent.take(tick.p);
        self.ticks += 1;
    }

    /// Per axis, what rounding alone can show of velocity, acceleration and jerk (mm units).
    fn floors(&self, period: f64) -> [[f64; 3]; 3] {
        let per_axis = self.extent.0.map(|x| Differences::rounding(x, period));
        std::array::from_fn(|order| per_axis.map(|f| f[order] / MM))
    }

    /// The drives' maxima (with `--servo`: the engine keeps their outputs once per step).
    fn take_drives(&mut self, outputs: &Outputs) {
        let axes = &outputs.axes;
        self.following_error.take(axes.map(|s| s.following_error));
        self.torque.take(axes.map(|s| s.motor_torque));
        self.contour = self.contour.max(outputs.contour_error);
    }
}

pub fn run(args: &RunArgs) -> ExitCode {
    match run_inner(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("{message}");
            ExitCode::from(2)
        }
    }
}

fn load_machine(path: Option<&str>) -> Result<Machine, String> {
    match path {
        Some(path) => {
            let toml = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
            Machine::from_toml(&toml, path).map_err(|e| e.to_string())
        }
        None => Ok(Machine::default()),
    }
}

/// A bar over the program's bytes, with percentage and ETA, when stderr is a terminal. The
/// position is what the reader has read: it runs the look-ahead ahead of the motion, and an O-word
/// loop takes it back.
fn progress_bar(program_bytes: u64) -> Option<ProgressBar> {
    std::io::stderr().is_terminal().then(|| {
        let bar = ProgressBar::new(program_bytes.max(1));
        bar.set_style(
            ProgressStyle::with_template(
                "{wide_bar} {percent:>3}% of {total_bytes}  {msg}  elapsed {elapsed}, ETA {eta}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    })
}

fn run_inner(args: &RunArgs) -> Result<(), String> {
    // The program is streamed line by line (memory does not grow with its length).
    let file = std::fs::File::open(&args.program).map_err(|e| format!("{}: {e}", args.program))?;
    let program_bytes = file.metadata().map(|m| m.len()).unwrap_or(0);
    let machine = load_machine(args.machine.as_deref())?;
    let source = ProgramSource::File(PathBuf::from(&args.program));
    let mut engine = Engine::new(source, &args.program, &machine)
        .map_err(|e| e.to_string())?
        .with_servo(args.servo);
    let mut csv = match &args.csv {
        Some(path) => {
            let w = csv::Writer::from_path(path).map_err(|e| format!("{path}: {e}"))?;
            Some((path.clone(), w))
        }
        None => None,
    };
    let bar = progress_bar(program_bytes);
    let mut max = Maxima::default();
    let mut emitted = Differences::new(engine.tick().p, machine.interpolation_period);
    while !engine.finished() && engine.time() < args.max_time {
        engine.step().map_err(|e| e.to_string())?;
        engine
            .check_outputs()
            .map_err(|m| format!("{}: {m}", args.program))?;
        // Read in place (a tick is 168 bytes); the drives' outputs only when simulated.
        let tick = engine.tick();
        max.take(tick, emitted.push(tick.p));
        let outputs = args.servo.then(|| engine.outputs());
        if let Some(outputs) = &outputs {
            max.take_drives(outputs);
        }
        if let Some((path, w)) = csv.as_mut() {
            let axes = outputs.map_or_else(|| engine.axes(), |o| o.axes);
            let row = CsvRow::new(tick, &axes);
            w.serialize(row).map_err(|e| format!("{path}: {e}"))?;
        }
        if let Some(bar) = bar.as_ref().filter(|_| max.ticks % 1000 == 0) {
            bar.set_position(engine.program_offset() as u64);
            bar.set_message(format!("line {}, t = {:.1} s", tick.line, tick.t));
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    if let Some((path, mut w)) = csv {
        w.flush().map_err(|e| format!("{path}: {e}"))?;
    }
    if !engine.finished() {
        return Err(not_finished(&engine, &args.program, args.max_time));
    }
    print_summary(args, &machine, &engine, &max);
    Ok(())
}

fn print_summary(args: &RunArgs, machine: &Machine, engine: &Engine, max: &Maxima) {
    let tick = engine.tick();
    let mut summary = serde_json::json!({
        "program": args.program,
        "profile": machine.profile.name(),
        "corner": machine.corner.name(),
        "interpolation_period_s": machine.interpolation_period,
        "total_time_s": engine.finish_time().unwrap_or(engine.time()),
        "motion_time_s": engine.motion_time(),
        "ticks": max.ticks,
        "path_length_mm": tick.distance / MM,
        "motion_blocks": engine.motion_blocks(),
        "end_position_mm": tick.p.map(|x| x / MM),
        "max_axis_velocity_mm_s": max.v.mm(),
        "max_axis_acceleration_mm_s2": max.a.mm(),
        "max_axis_jerk_mm_s3": max.j.mm(),
    });
    if args.servo {
        summary["max_following_error_mm"] = serde_json::json!(max.following_error.mm());
        summary["max_contour_error_mm"] = serde_json::json!(max.contour / MM);
        summary["max_motor_torque_n_m"] = serde_json::json!(max.torque.0);
    }
    if args.json {
        println!("{summary}");
    } else {
        for (label, text) in human_summary(args, machine, engine, max) {
            println!("{label:22} {text}");
        }
    }
}

/// The rows of the summary a person reads: rounded, maxima beside the machine's limits.
fn human_summary(
    args: &RunArgs,
    machine: &Machine,
    engine: &Engine,
    max: &Maxima,
) -> Vec<(&'static str, String)> {
    let tick = engine.tick();
    let [v_lim, a_lim, j_lim] = summary::axis_limits(machine, MM);
    let [v_floor, a_floor, j_floor] = max.floors(machine.interpolation_period);
    let period_ms = machine.interpolation_period * 1e3;
    let mut rows = vec![
        ("program", args.program.clone()),
        (
            "feed law / corners",
            format!("{} / {}", machine.profile.name(), machine.corner.name()),
        ),
        (
            "total time",
            format!(
                "{:.3} s (motion {:.3} s, {} ticks of {period_ms} ms)",
                engine.finish_time().unwrap_or(engine.time()),
                engine.motion_time(),
                max.ticks
            ),
        ),
        (
            "path length",
            format!(
                "{:.3} mm in {} motion blocks",
                tick.distance / MM,
                engine.motion_blocks()
            ),
        ),
        ("end position", summary::per_axis(tick.p.map(|x| x / MM), 3, "mm")),
        (
            "max axis velocity",
            summary::against_limits(max.v.mm(), v_lim, v_floor, "mm/s"),
        ),
        (
            "max axis acceleration",
            summary::against_limits(max.a.mm(), a_lim, a_floor, "mm/s²"),
        ),
        (
            "max axis jerk",
            summary::against_limits(max.j.mm(), j_lim, j_floor, "mm/s³"),
        ),
    ];
    if let Some(note) = summary::corner_note(machine.corner) {
        rows.push(("", format!("({note})")));
    }
    if args.servo {
        let following = max.following_error.mm().map(|v| v * 1e3);
        rows.push(("max following error", summary::per_axis(following, 2, "µm")));
        rows.push(("max contour error", format!("{:.2} µm", max.contour / MM * 1e3)));
        let torque = max.torque.0;
        let d = summary::decimals(torque.iter().copied().fold(0.0, f64::max));
        rows.push(("max motor torque", summary::per_axis(torque, d, "N·m")));
    }
    rows
}

/// `FILE:LINE:1: not finished after --max-time …: why` for the line being executed.
fn not_finished(engine: &Engine, program: &str, max_time: f64) -> String {
    let line = engine.tick().line;
    let why = match engine.executing() {
        Some((block, left)) => match block.segment {
            Segment::Dwell { seconds, .. } => {
                format!("dwelling (G4 P{seconds}), {left:.3} s of the dwell left")
            }
            // The path feed, not F: in G93 F is 1/min, in G20 in/min.
            _ if block.v_feed * 60.0 / MM < 1.0 => format!(
                "feed too low: {} mm/min along the path, {left:.3} s of this block left",
                block.v_feed * 60.0 / MM
            ),
            _ => format!(
                "moving at {:.3} mm/min (the block's path feed {} mm/min), {left:.3} s of this block left",
                engine.tick().feed * 60.0 / MM,
                block.v_feed * 60.0 / MM
            ),
        },
        None => "no block in progress: the path planner has not delivered the next segment".into(),
    };
    format!(
        "{program}:{line}:1: not finished after --max-time {max_time} s of simulated time: \
         executing line {line}, {why}"
    )
}

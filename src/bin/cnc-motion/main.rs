//! `cnc-motion` command line: `profile` (one block's feed law), `run` (a whole program), `package`
//! (write the FMU). Inputs and outputs in mm and seconds; the library works in SI.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use clap::builder::TypedValueParser;
use clap::{Parser, Subcommand};
use cnc_motion::feed::{BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use std::process::ExitCode;

mod run;
mod summary;

use cnc_motion::si::MM;

#[derive(Parser)]
#[command(
    name = "cnc-motion",
    version,
    about = "CNC motion controller: G-code to jerk-limited axis motion"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Plan one block with a feed law and print its durations and peaks.
    Profile {
        /// Block length (mm).
        #[arg(long)]
        length: f64,
        /// Entry speed (mm/s).
        #[arg(long, default_value_t = 0.0)]
        v_start: f64,
        /// Wanted exit speed (mm/s).
        #[arg(long, default_value_t = 0.0)]
        v_end: f64,
        /// Feed / maximum speed (mm/s).
        #[arg(long)]
        v_max: f64,
        /// Acceleration limit (mm/s²).
        #[arg(long)]
        a_max: f64,
        /// Jerk limit (mm/s³).
        #[arg(long)]
        j_max: f64,
        /// Snap limit (mm/s⁴), jerk15 only.
        #[arg(long, default_value_t = 6.0e6)]
        snap: f64,
        /// Feed law (the names of the machine file's `profile`).
        #[arg(long, default_value = "scurve7", value_parser = kind_parser())]
        kind: ProfileKind,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Run a G-code program through planner and interpolator (and the servo model).
    Run(run::RunArgs),
    /// Write the FMU to target/fmu/CncMotion.fmu (or --output).
    Package {
        #[arg(long, default_value = "target/fmu/CncMotion.fmu")]
        output: String,
        /// Platforms whose binaries go in (built beforehand: `make cross` for win64 and
        /// aarch64-linux; aarch64-linux goes into the FMI 3.0 archive only).
        #[arg(long, default_value = fmi2::package::ALL_PLATFORMS)]
        platforms: String,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Profile {
            length,
            v_start,
            v_end,
            v_max,
            a_max,
            j_max,
            snap,
            kind,
            json,
        } => profile(length, v_start, v_end, v_max, a_max, j_max, snap, kind, json),
        Command::Run(args) => run::run(&args),
        Command::Package { output, platforms } => package(&output, &platforms),
    }
}

/// `--kind` takes the library's names (clap lists them in `--help` and in its error).
fn kind_parser() -> impl TypedValueParser<Value = ProfileKind> {
    clap::builder::PossibleValuesParser::new(ProfileKind::ALL.map(ProfileKind::name))
        .try_map(|name| name.parse::<ProfileKind>())
}

fn fail(message: impl std::fmt::Display) -> ExitCode {
    eprintln!("{message}");
    ExitCode::from(2)
}

#[allow(clippy::too_many_arguments)]
fn profile(
    length: f64,
    v_start: f64,
    v_end: f64,
    v_max: f64,
    a_max: f64,
    j_max: f64,
    snap: f64,
    kind: ProfileKind,
    json: bool,
) -> ExitCode {
    let checks = [
        ("--length", length, true),
        ("--v-start", v_start, true),
        ("--v-end", v_end, true),
        ("--v-max", v_max, false),
        ("--a-max", a_max, false),
        ("--j-max", j_max, false),
        ("--snap", snap, false),
    ];
    for (name, value, zero_ok) in checks {
        if !value.is_finite() || value < 0.0 || (!zero_ok && value == 0.0) {
            return fail(format!("{name}: must be a finite {} number, got {value}", {
                if zero_ok {
                    "non-negative"
                } else {
                    "positive"
                }
            }));
        }
    }
    if v_start > v_max {
        return fail(format!("--v-start: {v_start} mm/s is above --v-max {v_max} mm/s"));
    }
    let req = BlockRequest {
        length: length * MM,
        v_in: v_start * MM,
        v_out: v_end.min(v_max) * MM,
        v_feed: v_max * MM,
        limits: Limits {
            v_max: v_max * MM,
            a_max: a_max * MM,
            j_max: j_max * MM,
            snap_max: snap * MM,
        },
    };
    let p = Profile::plan(kind, &req);
    let peaks = sample_peaks(&p);
    let phases = p.phases();
    if json {
        let out = serde_json::json!({
            "kind": kind.name(),
            "duration_s": p.duration(),
            "length_mm": p.length() / MM,
            "v_peak_mm_s": peaks[0] / MM,
            "a_peak_mm_s2": peaks[1] / MM,
            "j_peak_mm_s3": peaks[2] / MM,
            "v_end_mm_s": p.v_end() / MM,
            "phases_s": phases,
        });
        println!("{out}");
    } else {
        println!("kind        {}", kind.name());
        println!("duration    {:.9} s", p.duration());
        println!("length      {:.9} mm", p.length() / MM);
        println!("v_peak      {:.6} mm/s", peaks[0] / MM);
        println!("a_peak      {:.6} mm/s²", peaks[1] / MM);
        println!("j_peak      {:.6} mm/s³", peaks[2] / MM);
        println!("v_end       {:.6} mm/s", p.v_end() / MM);
        println!("phases      {:?} s", phases);
    }
    ExitCode::SUCCESS
}

/// Peaks of |v|, |a|, |j|: at every phase boundary and mid-phase, and on a fine grid (the laws with
/// polynomial acceleration peak inside a phase).
fn sample_peaks(p: &Profile) -> [f64; 3] {
    let mut peaks = [0.0f64; 3];
    let mut take = |t: f64| {
        let k = p.at(t);
        peaks[0] = peaks[0].max(k.v.abs());
        peaks[1] = peaks[1].max(k.a.abs());
        peaks[2] = peaks[2].max(k.j.abs());
    };
    let mut t0 = 0.0;
    for d in p.phases() {
        for f in [1e-12, 0.5, 1.0 - 1e-12] {
            take(t0 + f * d);
        }
        t0 += d;
    }
    let n = 4000;
    let duration = p.duration();
    for i in 0..=n {
        take(duration * i as f64 / n as f64);
    }
    peaks
}

fn package(output: &str, platforms: &str) -> ExitCode {
    match cnc_motion::package::write_fmu(std::path::Path::new(output), platforms) {
        Ok(()) => {
            println!("{output}");
            ExitCode::SUCCESS
        }
        Err(e) => fail(format!("package: {e}")),
    }
}

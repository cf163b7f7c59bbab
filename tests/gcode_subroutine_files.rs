//! Issue 20: subroutine files (LinuxCNC "O Codes", "Calling Files": "To call a separate file
//! with a subroutine name the file the same as your call and include a sub and endsub in the
//! file … The file names are lowercase letters only so o<MyFile> is converted to o<myfile>").
//! `<name>.ngc` is looked for in the program file's directory, then in the machine file's
//! `subroutine_path` (LinuxCNC's PROGRAM_PREFIX and SUBROUTINE_PATH); a program given as text
//! has only the latter. Files are streamed as the program is; errors are located in the file
//! they are in. End positions as LinuxCNC reaches them, hand-computed in the comments.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use cnc_motion::gcode::{Block, Motion, ProgramSource, Reader};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A fresh directory under the system's temporary one, with `files` (name, text) in it.
fn dir_with(tag: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("subfiles_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (name, text) in files {
        let path = dir.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

/// End points (mm, rounded to 1e-9) of the moves of a reader, or its error.
fn ends(mut r: Reader) -> Result<Vec<[f64; 3]>, String> {
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        if let Block {
            motion: Motion::Linear { to } | Motion::Rapid { to } | Motion::Arc { to, .. },
            ..
        } = b
        {
            out.push(to.map(|v| (v * 1e12).round() / 1e9));
        }
    }
    Ok(out)
}

fn file_reader(path: &Path, machine: &Machine) -> Reader {
    let name = path.display().to_string();
    Reader::new(ProgramSource::File(path.to_path_buf()), &name, [0.0; 3]).with_machine(machine)
}

/// "Calling Files", Named File Example: `o<MyFile> call` in a program loads myfile.ngc beside
/// it (lower case), whose `o<myfile> sub … endsub` runs with the call's arguments; lines after
/// its endsub (the example's M2) are not run. The program then goes on: X = 2·3 = 6 in the
/// file, then X7 in the program.
#[test]
fn a_call_loads_the_file_beside_the_program() {
    let dir = dir_with(
        "beside",
        &[
            ("main.ngc", "G21 F100\no<MyFile> call [3]\nG1 X7\nM2\n"),
            (
                "myfile.ngc",
                "(filename myfile.ngc)\no<myfile> sub\n  G1 X[2 * #1]\no<myfile> endsub\nM2\n",
            ),
        ],
    );
    let got = ends(file_reader(&dir.join("main.ngc"), &Machine::default()));
    assert_eq!(got.unwrap(), vec![[6.0, 0.0, 0.0], [7.0, 0.0, 0.0]]);
    std::fs::remove_dir_all(dir).unwrap();
}

/// `subroutine_path` (relative to the machine file): a program given as text finds its files
/// there only; a numbered call `o123 call` loads 123.ngc ("Numbered File Example"). Loops,
/// return values and a call from one file into another run as in the program: the file's sub
/// repeats a G91 X1 move #1 times and returns #1·10, which the program moves to in Y.
#[test]
fn subroutine_path_of_the_machine_file() {
    let dir = dir_with(
        "path",
        &[
            ("machine/m.toml", "subroutine_path = [\"../subs\", \"/nonexistent\"]\n"),
            (
                "subs/steps.ngc",
                "o<steps> sub\no1 repeat [#1]\nG91 G1 X1\no1 endrepeat\nG90\no123 call\no<steps> endsub [#1 * 10]\n",
            ),
            ("subs/123.ngc", "o123 sub\nG1 Z-1\no123 endsub\n"),
        ],
    );
    let m_path = dir.join("machine/m.toml");
    let m = Machine::from_toml(
        &std::fs::read_to_string(&m_path).unwrap(),
        m_path.to_str().unwrap(),
    )
    .unwrap();
    assert_eq!(m.nc.subroutine_path[0], dir.join("machine/../subs"));
    let text = "G21 F100\no<steps> call [3]\nG1 Y#<_value>\nM2\n";
    let r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(&m);
    let got = ends(r).unwrap();
    assert_eq!(
        got,
        vec![
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [3.0, 0.0, 0.0],
            [3.0, 0.0, -1.0],
            [3.0, 30.0, -1.0]
        ]
    );
    // Without the key a program given as text has no directory to look in.
    let r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]);
    assert_eq!(
        ends(r).unwrap_err(),
        "t.ngc:2:1: o<steps> call: the program has no o<steps> sub (a program given as text has no \
         directory to find steps.ngc in: machine key subroutine_path)"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// Errors in a subroutine file are located in that file (`file:line:col`): LinuxCNC's
/// x-trim.ngc calls touchoff.ngc, which probes (G38.2, not supported: no probe input); a file
/// without its `sub` line is an error at the call; a file whose sub has no endsub at its sub.
#[test]
fn errors_are_located_in_the_file() {
    let touchoff = "o<touchoff> sub\n; the touch-off\nF10\nG38.2 Z-1.75 (Probe to find the surface)\no<touchoff> endsub\nM2\n";
    let dir = dir_with(
        "errors",
        &[
            (
                "x-trim.ngc",
                "G20\nG92 X0 Y0\no<touchoff> call [0.100] [0] [0.08]\nM2\n",
            ),
            ("touchoff.ngc", touchoff),
            ("nosub.ngc", "G0 X1\n"),
            ("noend.ngc", "\no<noend> sub\nG0 X1\n"),
            ("calls.ngc", "o<nosub> call\n"),
            ("calls2.ngc", "G0 X2\no<noend> call\n"),
            ("percent.ngc", "o<percent> sub\n%\no<percent> endsub\n"),
            ("calls3.ngc", "%\no<percent> call\n%\n"),
        ],
    );
    let m = Machine::default();
    let e = ends(file_reader(&dir.join("x-trim.ngc"), &m)).unwrap_err();
    let sub = dir.join("touchoff.ngc").display().to_string();
    assert_eq!(e, format!("{sub}:4:1: unsupported G38.2 (probing)"));
    let e = ends(file_reader(&dir.join("calls.ngc"), &m)).unwrap_err();
    let (main, nosub) = (dir.join("calls.ngc"), dir.join("nosub.ngc"));
    assert_eq!(
        e,
        format!(
            "{}:1:1: o<nosub> call: {} has no o<nosub> sub (LinuxCNC \"Calling Files\")",
            main.display(),
            nosub.display()
        )
    );
    let e = ends(file_reader(&dir.join("calls2.ngc"), &m)).unwrap_err();
    assert_eq!(
        e,
        format!(
            "{}:2:1: o<noend> sub without o<noend> endsub",
            dir.join("noend.ngc").display()
        )
    );
    // `%` demarcates the program ("File Requirements"), not a subroutine file.
    let e = ends(file_reader(&dir.join("calls3.ngc"), &m)).unwrap_err();
    let at = format!("{}:2:1: ", dir.join("percent.ngc").display());
    assert!(e.starts_with(&at), "{e}");
    std::fs::remove_dir_all(dir).unwrap();
}

/// An engine state saved while a subroutine file's loop runs restores to the same motion (the
/// file, its place and the call are part of the state), through the FMU's kind of program: a
/// file read whole, whose directory is searched as the command line searches it.
#[test]
fn engine_state_round_trip_inside_a_file() {
    let dir = dir_with(
        "state",
        &[
            ("p.ngc", "G21 F3000\n#<k> = 0\no1 while [#<k> LT 3]\no<tooth> call [#<k>]\n#<k> = [#<k> + 1]\no1 endwhile\nM2\n"),
            (
                "tooth.ngc",
                "o<tooth> sub\n#<n> = 0\no2 repeat [3]\nG1 X0\nG1 Y[#1 + #<n>] X1\n#<n> = [#<n> + 0.1]\no2 endrepeat\no<tooth> endsub\n",
            ),
        ],
    );
    let path = dir.join("p.ngc");
    let text: Arc<str> = Arc::from(std::fs::read_to_string(&path).unwrap());
    let m = Machine::default();
    let new = || Engine::new(ProgramSource::FileText(text.clone(), path.clone()), "p.ngc", &m).unwrap();
    let mut a = new();
    a.advance(0.5).unwrap();
    let state = a.save_state();
    let mut b = new();
    b.restore_state(&state).unwrap();
    while !a.finished() {
        a.advance(0.01).unwrap();
        b.advance(0.01).unwrap();
        assert_eq!(a.tick().p, b.tick().p);
    }
    let end = b.tick().p;
    assert!(
        (end[0] - 1e-3).abs() < 1e-12 && (end[1] - 2.2e-3).abs() < 1e-12,
        "{end:?}"
    );
    // A program given as text does not search the file's directory.
    let e = Engine::new(text.clone(), "p.ngc", &m).unwrap_err().to_string();
    assert!(
        e.starts_with("p.ngc:4:1: o<tooth> call: the program has no o<tooth> sub"),
        "{e}"
    );
    std::fs::remove_dir_all(dir).unwrap();
}

/// `subroutine_path` in the machine file: at most LinuxCNC's 10 directories, each a non-empty
/// string; located errors otherwise.
#[test]
fn subroutine_path_key_is_checked() {
    let eleven: Vec<String> = (0..11).map(|k| format!("\"d{k}\"")).collect();
    let toml = format!("subroutine_path = [{}]\n", eleven.join(", "));
    let e = Machine::from_toml(&toml, "m.toml").unwrap_err().to_string();
    assert_eq!(
        e,
        "m.toml:1:19: subroutine_path: 11 directories, at most 10 (LinuxCNC's SUBROUTINE_PATH)"
    );
    let e = Machine::from_toml("subroutine_path = [\"\"]\n", "m.toml")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("m.toml:1:19: subroutine_path: each entry a directory"),
        "{e}"
    );
    let e = Machine::from_toml("subroutine_path = \"subs\"\n", "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("m.toml:1:19: "), "{e}");
    let m = Machine::from_toml("subroutine_path = [\"/abs\", \"rel\"]\n", "cfg/m.toml").unwrap();
    assert_eq!(
        m.nc.subroutine_path,
        [PathBuf::from("/abs"), PathBuf::from("cfg/rel")]
    );
}

//! Issue 11: MachineStructure refuses parameters out of their documented range and corrupted
//! serialized states, and never returns NaN outputs with status OK.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use fmi2::{set_by_name, Model, Value};
use machine_structure::MachineStructureFmu;

fn fmu() -> MachineStructureFmu {
    <MachineStructureFmu as Model>::new(None)
}

#[test]
fn extreme_parameters_are_refused_with_the_range() {
    for (name, x) in [
        ("x.mode1.frequency", 1e308),
        ("x.mode1.frequency", 5e-324),
        ("y.mode2.damping", 1e308),
        ("z.mode1.mass", 5e-324),
        ("z.mode1.mass", 1e308),
        ("x.couplingMass", 1e308),
        ("y.driveForce", 1e308),
    ] {
        let mut f = fmu();
        let e = set_by_name(&mut f, name, Value::Real(x)).expect_err(name);
        assert!(e.contains("out of range ("), "{name} = {x}: {e}");
    }
    // The bounds themselves are accepted.
    let mut f = fmu();
    set_by_name(&mut f, "x.mode1.frequency", Value::Real(1e4)).unwrap();
    set_by_name(&mut f, "x.couplingMass", Value::Real(1e5)).unwrap();
    f.exit_initialization().unwrap();
    f.do_step(1e-3).unwrap();
}

/// Tiny deterministic generator (xorshift64*), so the corruption cases are the same every run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
}

#[test]
fn corrupted_states_are_refused_or_stay_finite() {
    let mut f = fmu();
    set_by_name(&mut f, "x.couplingMass", Value::Real(50.0)).unwrap();
    f.exit_initialization().unwrap();
    set_by_name(&mut f, "x.driveForce", Value::Real(2000.0)).unwrap();
    for _ in 0..20 {
        f.do_step(1e-3).unwrap();
    }
    // The state is binary (postcard): overwrite 8 bytes at a random offset with an extreme f64,
    // which lands on a number of the state or across two of them.
    let good = f.serialize();
    let numbers = [1e308, -1e308, 5e-324, 0.0, -1.0, 1e30, f64::NAN, f64::INFINITY];
    let (mut refused, mut accepted) = (0, 0);
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..1000 {
        let at = (rng.next() % (good.len() - 8) as u64) as usize;
        let mut bad = good.clone();
        bad[at..at + 8].copy_from_slice(&numbers[(rng.next() % 8) as usize].to_le_bytes());
        let mut g = fmu();
        match g.deserialize(&bad) {
            Err(e) => {
                assert!(e.starts_with("MachineStructure state: "), "{e}");
                refused += 1;
            }
            Ok(()) => {
                accepted += 1;
                for k in 0..50 {
                    if g.do_step(1e-3).is_err() {
                        break;
                    }
                    for vr in 0..3 {
                        let s = &g.0;
                        let out = [s.deflection(vr), s.acceleration(vr), s.load_force(vr)];
                        assert!(
                            out.iter().all(|v| v.is_finite()),
                            "NaN with OK at step {k} (bytes {at}…)"
                        );
                    }
                }
            }
        }
    }
    eprintln!("corrupted states: {refused} refused, {accepted} accepted and finite");
    assert!(refused > 100 && accepted > 100, "{refused} / {accepted}");
}

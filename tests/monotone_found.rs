//! The cases the random search of tests/monotone_props.rs found, kept as they were found (the
//! machine as a user writes it in a machine file, the program as printed): each lengthened a
//! program for a larger tolerance or a higher limit before the change its comment names, and
//! fails without it.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use std::fmt::Write;
use std::sync::Arc;

/// Relative slack of "never longer", as in tests/monotone_props.rs.
const SLACK: f64 = 1e-3;

/// Motion time of the program on the machine (s), run to its end.
fn time(text: &str, m: &Machine) -> f64 {
    let mut e = Engine::new(Arc::from(text), "p.ngc", m).expect("valid program");
    while !e.finished() {
        e.step().expect("no runtime error");
    }
    e.motion_time()
}

/// The machine of a found case: its tolerance (mm) and each axis's velocity (mm/min),
/// acceleration (mm/s²) and jerk (mm/s³), read from a machine file as a user would write it.
fn found_machine(tolerance: f64, axes: [[f64; 3]; 3]) -> Machine {
    let mut text = format!("max_feed_mm_min = 60000\npath_tolerance_mm = {tolerance}\n");
    for (name, [v, a, j]) in ["x", "y", "z"].iter().zip(axes) {
        write!(
            text,
            "[axis.{name}]\nmax_velocity_mm_min = {v}\nmax_acceleration_mm_s2 = {a}\nmax_jerk_mm_s3 = {j}\n"
        )
        .unwrap();
    }
    Machine::from_toml(&text, "m.toml").expect("a valid machine")
}

/// A found case: `program` on the machine of `axes` runs no longer at the larger tolerance
/// (mm) than at the smaller.
fn assert_larger_tolerance_not_longer(program: &str, axes: [[f64; 3]; 3], [small, large]: [f64; 2]) {
    let low = time(program, &found_machine(small, axes));
    let high = time(program, &found_machine(large, axes));
    assert!(high <= low * (1.0 + SLACK), "{high} s > {low} s");
}

#[path = "monotone_found/fit.rs"]
mod fit;

/// A case `tolerance_failure_rate` found (seed 5): at 2.59 times the tolerance the transition
/// between the second and third arcs cut all of the second (94 µm), so it followed the first
/// arc's chain directly and joined it, at that chain's 3.4 mm/s, where its cost had counted on
/// the second arc's 5.5 mm/s: 0.153 s against 0.124 s. A cut that leaves nothing of the span
/// before runs no faster than that span's entry (path/junction.rs, `Search::speed`).
#[test]
fn a_larger_tolerance_does_not_cut_a_whole_arc_into_a_slower_chain() {
    let axes = [
        [3529.33, 1025.49, 1551723.48],
        [11088.40, 3109.23, 47273685.82],
        [4270.40, 238.98, 3461.02],
    ];
    let program = "G21 G90 G17 G64 F429.3
G3 X0.0003 Y0.0225 Z0.0000 I0.0018 J0.0112
G2 X-0.0103 Y0.0832 Z0.0000 I-0.0043 J0.0305
G2 X0.3693 Y-0.0638 Z-0.0635 I0.0760 J-0.3674
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.00985, 0.02548]);
}

/// A case `tolerance_failure_rate` found (seed 3): the program starts at rest on a 0.27 mm arc.
/// At 2.71 times the tolerance the transition to the next arc cut 0.23 mm of it, costed at the
/// 14.9 mm/s the whole arc reaches from rest; the 43 µm it left reaches far less, so the longer
/// transition started slower: 0.185 s against 0.180 s. A cut is costed no faster than the span
/// before reaches from its entry over what the cut leaves of it (path/junction.rs, `Search::speed`).
#[test]
fn a_larger_tolerance_does_not_cut_into_an_arc_still_rising_from_rest() {
    let axes = [
        [5485.22, 807.23, 474706292.75],
        [2403.17, 1489.44, 86177967.64],
        [12550.48, 207.04, 26030.45],
    ];
    let program = "G21 G90 G17 G64 F3975.7
G3 X0.2386 Y0.1112 Z0.0000 I-0.0001 J0.3117
G3 X1.9439 Y3.6348 Z0.9534 I-6.1064 J5.1296
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.01035, 0.02809]);
}

/// A case `tolerance_failure_rate` found (seed 5): the program ends on a 2.84 mm arc. At 3.81
/// times the tolerance the transition from the 33.7 mm line before it cut half of it, 1.42 mm,
/// costed as if the arc ran on at its own 13.9 mm/s after it; it stops at the program's end,
/// from at most 11.8 mm/s over its length: 1.789 s against 1.745 s. The last span before a stop
/// is known to end at rest, and a cut is costed no faster than it stops from over what is left
/// (path/smooth.rs, `SmoothBuilder::stop`; path/junction.rs, `Search::speed`).
#[test]
fn a_larger_tolerance_does_not_cut_into_an_arc_that_stops_the_program() {
    let axes = [
        [4185.95, 480.23, 1346.67],
        [5781.84, 3690.82, 184905454.69],
        [1827.93, 3745.09, 307299079.57],
    ];
    let program = "G21 G90 G17 G64 F1823.7
G3 X0.0010 Y0.0005 Z0.0001 I0.0000 J0.0014
G1 X22.4094 Y24.6497 Z5.1824
G3 X21.4055 Y26.8339 Z5.1824 I-1.2268 J0.7590
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.04813, 0.18342]);
}

/// A case `tolerance_failure_rate` found (seed 1): five arcs. From 2.6 times the tolerance the
/// transition between the third and fourth (1.51 mm at 33.6 mm/s) and then the fourth arc
/// (1.38 mm at 34.6 mm/s) joined the 0.59 mm of the third arc (27.6 mm/s) in one chain, which ran
/// them all at 27.6 mm/s: 0.553 s against 0.538 s. Each side reaches 27.6 mm/s from rest within
/// its length, so apart no ramp need pass through their junction and its block end costs
/// nothing: they are not joined (path/smooth.rs, `joined_loss`).
#[test]
fn a_larger_tolerance_does_not_join_arcs_that_each_reach_the_slower_speed() {
    let axes = [
        [1655.49, 3678.73, 156239.94],
        [7293.86, 3571.07, 143009462.25],
        [1379.1, 445.21, 225553444.33],
    ];
    let program = "G21 G90 G17 G64 F3040.3
G3 X9.6645 Y-0.2752 Z2.3063 I5.6379 J28.1605
G1 X9.6837 Y-0.2740 Z2.3044
G3 X10.5770 Y0.5361 Z2.3044 I0.0542 J0.8379
G2 X11.4233 Y2.4144 Z2.3044 I2.3530 J0.0696
G2 X11.4357 Y2.4112 Z2.3005 I0.0051 J-0.0061
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.008308, 0.021601]);
}

/// A case `limit_failure_rate` found (seed 4): two lines, the second (1.25 mm) the last before
/// the program's end. At 2.51 times every axis's velocity limit the corner stopped instead of
/// taking its transition: its cost counted the second line as running on at 35 mm/s after a
/// stop, the most it stops from over its whole length, where from rest it reaches far less:
/// 0.250 s against 0.240 s. The side that ends at a stop is costed by its block from the
/// transition's speed to rest over what is left of it (path/junction/cost.rs, `local_cost`).
#[test]
fn a_higher_velocity_limit_does_not_stop_before_the_last_line() {
    let program = "G21 G90 G17 G64 F8399.1
G1 X1.5137 Y-5.0667 Z0.0042
G1 X1.8664 Y-6.2505 Z-0.1708
M30
";
    let (a, j) = ([319.32, 2626.14, 3255.83], [581931443.67, 524119117.64, 3940.46]);
    let axes = |v: [f64; 3]| [0, 1, 2].map(|k| [v[k], a[k], j[k]]);
    let low = time(
        program,
        &found_machine(0.08683, axes([1885.04, 3741.59, 1789.42])),
    );
    let high = time(
        program,
        &found_machine(0.08683, axes([4735.22, 9398.87, 4495.02])),
    );
    assert!(high <= low * (1.0 + SLACK), "{high} s > {low} s");
}

/// A case `tolerance_failure_rate` found (seed 3): a 12.2 mm line, a 4.5 mm arc and a tight
/// 0.12 mm arc. At 2.85 times the tolerance the corner between the line and the first arc took
/// a longer cut (1.58 mm instead of 1.33), costed as if the arc ran on at its own 51 mm/s; it
/// slows to 2 mm/s for the corner at its end: 0.765 s against 0.730 s. A span's junction waits
/// for the span after it, and the ceiling of the transition there bounds how fast it is counted
/// at the corner before (path/smooth.rs, `junction`; path/junction.rs, `corner_ceiling`).
#[test]
fn a_larger_tolerance_does_not_cut_into_an_arc_that_slows_for_its_next_corner() {
    let axes = [
        [4993.55, 463.09, 647225283.68],
        [4150.38, 586.30, 3069.45],
        [2534.01, 3283.39, 18032.83],
    ];
    let program = "G21 G90 G17 G64 F10711.0
G1 X1.4887 Y-0.0003 Z0.3624
G1 X13.6824 Y-0.0025 Z-0.2426
G3 X17.7120 Y1.6461 Z-0.2426 I0.0010 J5.7464
G3 X17.7296 Y1.7554 Z-0.2426 I-0.0655 J0.0666
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.03423, 0.09762]);
}

/// A case `tolerance_failure_rate` found (seed 2): a fitted curve of 0.98 mm between two long
/// arcs. Its corner with the arc after it was estimated, when the corner before it was chosen,
/// as if that corner's transition might use all of the curve: at 3 times the tolerance 23.6 mm/s
/// where it then ran at 18.5, so the corner before took a longer cut to meet it and the program
/// ran 2.6494 s against 2.6414. The far corner is now estimated within the half of a span that
/// the corner before it leaves at least (path/junction.rs, `corner_ceiling`): 18.6 mm/s at both
/// tolerances, and 2.6344 s at both.
#[test]
fn a_larger_tolerance_does_not_count_on_all_of_a_short_span_at_its_far_corner() {
    let axes = [
        [8698.91363085605, 4662.674745841597, 2619.511333658117],
        [8204.310067342487, 1462.4688176222119, 716071076.23949],
        [4840.314852850144, 3245.01623009762, 11820821.110568725],
    ];
    let program = "G21 G90 G17 G64 F6649.0
G2 X0.0001 Y-0.0064 Z0.0000 I0.0000 J-0.0032
G2 X-7.0246 Y0.1350 Z0.4039 I-1.9465 J77.8455
G2 X-11.7221 Y-3.7789 Z-1.3823 I-4.6578 J0.8143
G2 X-11.8120 Y-3.7438 Z-1.3823 I0.0522 J0.2662
G2 X-29.1228 Y16.1029 Z-1.3823 I23.1422 J37.6580
G1 X-29.2537 Y16.4002 Z-1.3194
G1 X-29.5169 Y16.9980 Z-1.3206
G3 X-41.2093 Y10.9888 Z4.6239 I-6.0266 J-2.6535
G1 X-40.5622 Y9.8963 Z4.6710
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.058531380856831586, 0.17612092499820622]);
}

/// A case `make fuzz` found (PROPTEST_RNG_SEED 1216487744): one arc of R 8.85 mm from rest to
/// rest on axes of low jerk (X 4222, Z 1000 mm/s³), every acceleration limit raised 1.66 times:
/// 1.6020 s against 1.5997 s (from 1.1 times on it only grew). Each speed band's pair reserved
/// acceleration for the jerk's cross term up to the free acceleration, so a higher acceleration
/// limit left the band less jerk. The reserve now comes from the jerk limits alone (path/arc.rs,
/// `band_pairs`).
#[test]
fn a_higher_acceleration_limit_does_not_slow_a_single_arc() {
    let program = "G21 G90 G17 G64 F7122.3
G3 X-1.1839 Y17.6106 Z0.0000 I0.0000 J8.8451
M30
";
    let (v, j) = ([1192.62, 4725.08, 1000.0], [4221.52, 37279.91, 1000.0]);
    let axes = |a: [f64; 3]| [0, 1, 2].map(|k| [v[k], a[k], j[k]]);
    let low = [248.12, 2512.02, 199.53];
    for k in [1.1, 1.3, 1.658, 2.0] {
        let low_time = time(program, &found_machine(0.1, axes(low)));
        let high_time = time(program, &found_machine(0.1, axes(low.map(|a| a * k))));
        assert!(
            high_time <= low_time * (1.0 + SLACK),
            "×{k}: {high_time} s > {low_time} s"
        );
    }
}

/// A case `limit_failure_rate` found (seed 2): eight short moves on axes of low acceleration
/// and jerk (X 242 mm/s², Z 1102 mm/s³). From 1.35 times every acceleration limit on, the corner
/// between the 0.28 mm helical arc (from rest: a stop before it) and the 0.52 mm line after it
/// stopped: its cost counted the arc as rising to its own speed and the line as running on at
/// its own, where each is too short to, and put the stop 0.06 ms below the best cut. It cost
/// 10 ms: 0.3742 s against 0.3641 s at 2.1 times. A stop is now also compared with the best cut
/// by each side's block between the corner and its far end (the stop before the arc, the
/// ceiling at the line's end), and not taken where that says to run through
/// (path/junction.rs, `transition`).
#[test]
fn a_higher_acceleration_limit_does_not_stop_between_two_short_moves() {
    let program = "G21 G90 G17 G64 F816.1
G1 X-0.0031 Y0.0037 Z-0.0001
G1 X-0.0111 Y0.0170 Z0.0016
G3 X-0.0135 Y0.0223 Z0.0029 I-0.0140 J-0.0032
G3 X-0.0165 Y0.0204 Z0.0029 I-0.0014 J-0.0011
G3 X-0.0879 Y0.1555 Z-0.0545 I-0.0235 J0.0740
G1 X-0.0896 Y0.1542 Z-0.0544
G1 X-0.4899 Y-0.1597 Z0.0479
G3 X-0.5013 Y-0.1755 Z0.0479 I0.0105 J-0.0196
M30
";
    let (v, j) = ([2640.73, 1939.54, 2665.91], [8542394.23, 58726.68, 1102.10]);
    let axes = |a: [f64; 3]| [0, 1, 2].map(|k| [v[k], a[k], j[k]]);
    let low = [241.66, 668.58, 1018.79];
    let low_time = time(program, &found_machine(0.02264, axes(low)));
    for k in [1.35, 1.6, 2.103] {
        let high_time = time(program, &found_machine(0.02264, axes(low.map(|a| a * k))));
        assert!(
            high_time <= low_time * (1.0 + SLACK),
            "×{k}: {high_time} s > {low_time} s"
        );
    }
}

/// A case `tolerance_failure_rate` found (seed 4): before the program's end, the corner between
/// a 0.21 mm arc and a 0.96 mm one stops at the smaller tolerance; at 1.56 times it, a 0.19 mm
/// transition ran at 3.8 mm/s. The junction's cost ran the arc after it at the arc before's
/// 7.9 mm/s (as if joined in one chain), where its block to rest, apart, reaches 16.6: it counted
/// 25 ms gained from the transition against a stop where the plan gains 16, and the transition
/// was 7 ms slower than the stop (0.4781 s against 0.4674 s). A side whose far end is rest is
/// costed at its own speed (path/junction/cost.rs, `Side::beside`).
#[test]
fn a_larger_tolerance_does_not_cost_a_side_before_a_stop_at_its_slower_neighbour_speed() {
    let axes = [
        [1520.0, 524.5, 6.256e6],
        [7541.0, 2063.0, 17670.0],
        [1854.0, 1395.0, 8.825e8],
    ];
    let program = "G21 G90 G17 G64 F2463.6
G3 X1.2925 Y1.7248 Z0.0000 I0.0009 J1.3460
G1 X1.3180 Y1.2333 Z-0.0677
G3 X1.4027 Y1.0352 Z-0.0939 I0.3204 J0.0198
G2 X2.1248 Y1.5718 Z0.0561 I0.7744 J-0.2878
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.01926, 0.03007]);
}

/// A case `limit_failure_rate` found (seed 6), shortened to its last two moves: a line climbing
/// in Z and a flat arc that ends the program. From 1.7 times Z's acceleration limit on, the
/// transition between them ramps within 1.25 times the arc's ramp time, so it was joined to the
/// arc in one chain, whose limits are the worst of its pieces': the arc then stopped within the
/// transition's limits (×2.06: 0.2903 s against 0.2893 s, 0.2928 s at ×1.8). Where a stop
/// follows a piece whose ramp to rest lies within it, a slower ramp within the other side's
/// limits now counts against joining it by any margin (path/smooth.rs, `joined_loss`).
#[test]
fn a_higher_acceleration_limit_does_not_join_a_stopping_arc_to_a_slower_transition() {
    let program = "G21 G90 G17 G64 F8263.8
G1 X-0.6260 Y-3.3797 Z-0.5189
G2 X-6.5138 Y-3.8368 Z-0.5189 I-3.0046 J0.5542
M30
";
    let axes = |a_z: f64| {
        [
            [2673.62, 2115.62, 8.711e7],
            [13440.94, 3189.97, 99570.3],
            [14774.9, a_z, 3.39e8],
        ]
    };
    let low = time(program, &found_machine(0.0649, axes(484.85)));
    for k in [1.7, 1.8, 2.06, 2.4] {
        let high = time(program, &found_machine(0.0649, axes(484.85 * k)));
        assert!(high <= low * (1.0 + SLACK), "×{k}: {high} s > {low} s");
    }
}

/// A case `tolerance_failure_rate` found (seed 1): at 1.84 times the tolerance the transition
/// between two arcs of 10.2 and 3.6 mm radius was cut longer (3.7 mm at 52 mm/s) and joined in
/// one chain with the arc after it (8.4 mm at 60 mm/s), which brakes to the next corner. Each
/// ramps to 52 mm/s from rest within 1.25 times the other's time, but below 49.6 mm/s the chain
/// held 55 mm/s² where the arc alone holds 173 (the transition's limits near its top): within
/// the worst of both at every speed, it braked slower (0.9588 s against 0.9447 s). Joining is
/// judged by the ramp within that worst of both too (path/smooth.rs, `joined_loss`;
/// `Banded::worst_ramp`).
#[test]
fn a_larger_tolerance_does_not_join_a_transition_to_an_arc_whose_limits_are_tighter_elsewhere() {
    let axes = [
        [5156.40, 1597.76, 9757818.8],
        [8881.33, 1123.04, 16990.23],
        [3285.48, 263.52, 2868048.5],
    ];
    let program = "G21 G90 G17 G64 F8146.7
G3 X7.8210 Y-2.2798 Z-0.0001 I6.3088 J7.1829
G1 X10.5255 Y-1.8536 Z-0.4803
G3 X12.0719 Y17.8949 Z-3.4922 I-1.5769 J10.0583
G3 X8.4304 Y11.7648 Z-4.3307 I-1.5125 J-3.2482
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.0736, 0.1353]);
}

/// A case `tolerance_failure_rate` found (seed 2): at 3.7 times the tolerance the corner between
/// a 0.19 mm line and a small arc was first cut at its reach, where the transition is held to
/// the arc's 1.6 mm/s; the halved cut runs slower (1.4 mm/s) and cost more, so the search
/// stopped there, while cuts an octave further down, which leave the line room to brake from
/// the arc before it, cost less (the smaller tolerance's search found them). 0.4988 s against
/// 0.4880 s. Where the best cut is held below its own speed and the halving is slower than that,
/// one more halving is tried (path/junction.rs, `Search::cuts`).
#[test]
fn a_larger_tolerance_does_not_stop_the_cut_search_at_a_cut_held_to_its_neighbour() {
    let axes = [
        [11160.18, 1112.77, 13714001.4],
        [5059.78, 361.50, 1734.18],
        [1495.85, 921.16, 30398.49],
    ];
    let program = "G21 G90 G17 G64 F7654.5
G2 X0.2868 Y-0.2668 Z-0.0717 I0.0000 J-0.2875
G1 X0.2809 Y-0.4585 Z-0.0231
G2 X0.1868 Y-0.4953 Z-0.0231 I-0.0487 J-0.0142
G2 X0.0882 Y-0.4061 Z-0.0231 I0.0661 J0.1723
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.00715, 0.0265]);
}

/// A case `tolerance_failure_rate` found (seed 5): a 0.082 mm line from rest and a 0.168 mm one.
/// The smaller tolerance's first cut, 0.0455 mm, ran the corner at 6.85 mm/s, where the line
/// from rest reaches it over what the cut leaves; at 2.8 times the tolerance the whole line was
/// admitted and the grid's cuts compared: 0.0408 mm at 6.37 mm/s, and 0.0485 mm capped at 6.57
/// by the line's rise over the 0.033 mm it leaves (0.0475 s against 0.0464 s). The cut where that
/// rise meets the transition's speed is tried too (path/junction/crossing.rs).
#[test]
fn a_larger_tolerance_finds_the_cut_where_the_rise_from_rest_meets_the_corner() {
    let axes = [
        [10214.38, 760.34, 692344.99],
        [4063.32, 3616.96, 56147.22],
        [1478.56, 271.98, 518776073.83],
    ];
    let program = "G21 G90 G17 G64 F1247.4
G1 X0.0810 Y-0.0090 Z-0.0041
G1 X0.2352 Y-0.0674 Z0.0268
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.0029, 0.0081]);
}

/// A case `tolerance_failure_rate` found (seed 2): an arc, a 0.32 mm line and a 26.5 mm arc on
/// Z's jerk of 2715 mm/s³; 2.2507 s at 2.1 times the tolerance against 2.2447 s. A cut (or a
/// stop) at a corner is now also charged what the corner before loses where the span before
/// cannot drop from its entry (that corner's transition speed) to the cut's speed over what the
/// cut leaves of it (path/junction.rs, `Search::entry_drop`).
#[test]
fn a_larger_tolerance_does_not_cut_a_corner_slower_than_the_span_before_drops_to() {
    let axes = [
        [5375.56, 3633.94, 108420150.47],
        [1010.10, 346.24, 31369.42],
        [1281.58, 689.03, 2715.21],
    ];
    let program = "G21 G90 G17 G64 F3018.1
G3 X11.3977 Y4.4163 Z0.0000 I-0.0077 J16.9356
G1 X11.6308 Y4.6287 Z-0.0189
G3 X11.5816 Y27.8634 Z4.4029 I-10.5633 J11.5950
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.00437, 0.00929]);
}

/// A case `tolerance_failure_rate` found (seed 10): an S-bend between two arcs each held to Y's
/// velocity (30.9 mm/s). Every cut there costs the same at that speed, and the longest was
/// kept, but the transition runs above it on its own: at 4 times the tolerance 6.8 mm up to
/// 31.0 mm/s against the smaller tolerance's 5.7 mm up to 31.5 (0.7154 s against 0.7135 s). As
/// cheap and with more to gain above that speed, a shorter cut is taken (path/junction/tie.rs,
/// `Found::ties_faster`).
#[test]
fn a_larger_tolerance_does_not_keep_a_longer_transition_that_is_slower_on_its_own() {
    let axes = [
        [2915.48, 1951.52, 17296.73],
        [1854.87, 1463.62, 8498225.56],
        [11284.21, 2772.42, 609809.98],
    ];
    let program = "G21 G90 G17 G64 F7240.2
G3 X0.5793 Y-6.9756 Z0.0000 I5.5304 J-3.0745
G2 X-2.8149 Y-8.8566 Z0.0000 I-1.5436 J-1.2174
G3 X-2.8361 Y-8.8631 Z0.0007 I-0.0055 J-0.0200
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.0872, 0.3482]);
}

/// A case `tolerance_failure_rate` found (seed 12): at 3 times the tolerance the transition after
/// a 22.1 mm arc from rest runs at the arc's speed (28.6 mm/s), so joining them looked free, but
/// the arc then ramps from rest within the transition's top band (864 mm/s², 14 245 mm/s³
/// against its own 995 and 18 297): 1.2 times as slow, under what counts between pieces of one
/// speed, and 3.3 ms longer (0.920 s against 0.918 s). A chain that starts from rest counts its
/// ramp from it within the joined limits by any margin (path/smooth/joined.rs, `joined_loss`).
#[test]
fn a_larger_tolerance_does_not_join_an_arc_from_rest_to_a_transition_that_ramps_it_slower() {
    let axes = [
        [2252.20, 1172.46, 4067159.46],
        [13840.13, 1012.33, 21071.04],
        [3585.83, 1157.13, 1337099.54],
    ];
    let program = "G21 G90 G17 G64 F1715.7
G2 X13.9098 Y-13.9815 Z2.2608 I0.5216 J-13.3911
G1 X13.8747 Y-15.2786 Z2.3203
G3 X13.8779 Y-15.2914 Z2.3234 I0.0247 J-0.0007
M30
";
    assert_larger_tolerance_not_longer(program, axes, [0.002865, 0.00857]);
}

/// A case `limit_failure_rate` found (seed 11, here at 1.5 times Z's acceleration): a 0.23 mm arc
/// slows to 0.7 mm/s for the sharp corner after it, and the higher limit joined it to the
/// 0.076 mm transition before it, whose top band left 148 mm/s² instead of the arc's 238: it
/// ramped nearly to rest within that and ended 0.26 ms later (0.0948 s against 0.0946 s). A
/// piece that ends under a tenth of its speed joins a chain as one before a stop does
/// (path/smooth.rs, `NEARLY_STOPS`; path/smooth/joined.rs, `joined_loss`).
#[test]
fn a_higher_acceleration_limit_does_not_join_an_arc_that_nearly_stops_to_a_slower_transition() {
    let program = "G21 G90 G17 G64 F10054.9
G1 X0.9745 Y0.0000 Z-0.2122
G3 X1.1175 Y0.0209 Z-0.2177 I0.0000 J0.4990
G1 X1.1971 Y0.0447 Z-0.1988
G2 X1.4156 Y-0.0649 Z-0.2312 I0.0511 J-0.1708
G1 X1.4159 Y-0.0665 Z-0.2312
M30
";
    let axes = |z_acceleration: f64| {
        [
            [12705.05, 2791.84, 369580.11],
            [10706.94, 942.85, 351031.06],
            [2893.89, z_acceleration, 10460309.26],
        ]
    };
    let low = time(program, &found_machine(0.006235, axes(924.65)));
    let high = time(program, &found_machine(0.006235, axes(1386.97)));
    assert!(high <= low * (1.0 + SLACK), "{high} s > {low} s");
}

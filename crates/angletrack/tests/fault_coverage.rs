//! The fault-injection campaign of issue 36 (item 2): runs it, prints its table (between
//! the markers `scripts/fault-coverage.sh` extracts) and holds today's measured figures as
//! floors and ceilings, so that a change that loses coverage or adds false alarms fails,
//! and a fix that gains coverage raises its floor here. The targets (coverage of at
//! least 99 %, false alarms of at most 0.1 %, no fault latched on a healthy run) are
//! printed beside them, and held as floors where they are met.

use angletrack::fault_campaign::table::{
    COVERAGE_TARGET, FALSE_ALARM_TARGET, Latency, Row, worst_cases,
};
use angletrack::fault_campaign::{Campaign, Onset, ResolverKind, SensorKind};

/// The figures held for one row: fault, onset, wrong samples, coverage floor (%), false
/// alarms ceiling (%), worst latency ceiling (samples).
type Held = (
    &'static str,
    &'static str,
    usize,
    Option<f64>,
    f64,
    Option<usize>,
);

/// Today's figures, per fault and onset: the wrong samples (held within 10 %, so that an
/// injection that stops injecting fails), the coverage's floor in percent (the issue's
/// target, 99, where it is met; otherwise measured less one point; `None`: no wrong sample
/// today, and none is allowed), the false alarms' ceiling in percent (measured plus 0.1
/// point) and the worst latency's ceiling in samples (measured plus 10 %; `None`: a case is
/// never flagged today, or nothing is wrong).
const HELD: &[Held] = &[
    ("healthy", "—", 35, Some(99.00), 0.10, None),
    (
        "dead channel",
        "start",
        1006326,
        Some(99.00),
        0.10,
        Some(71),
    ),
    (
        "dead channel",
        "mid-run",
        414272,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "open channel",
        "start",
        1021236,
        Some(99.00),
        0.10,
        Some(71),
    ),
    (
        "open channel",
        "mid-run",
        414013,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "shorted channel",
        "start",
        1055245,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "shorted channel",
        "mid-run",
        590801,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "stuck channel",
        "start",
        839445,
        Some(99.00),
        0.10,
        Some(106),
    ),
    (
        "stuck channel",
        "mid-run",
        468470,
        Some(99.00),
        0.10,
        Some(19),
    ),
    (
        "clipping (gain 1.3 FS)",
        "start",
        200193,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "clipping (gain 1.3 FS)",
        "mid-run",
        110012,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "loss of excitation",
        "start",
        533578,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "loss of excitation",
        "mid-run",
        282241,
        Some(99.00),
        0.10,
        Some(18),
    ),
    (
        "brown-out (20 %)",
        "start",
        321107,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "brown-out (20 %)",
        "mid-run",
        110675,
        Some(99.00),
        0.10,
        Some(2),
    ),
    (
        "common-mode carrier",
        "start",
        29875,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "common-mode carrier",
        "mid-run",
        16473,
        Some(99.00),
        0.10,
        Some(9),
    ),
    (
        "imbalance (0.6)",
        "start",
        360828,
        Some(99.00),
        0.10,
        Some(36),
    ),
    (
        "imbalance (0.6)",
        "mid-run",
        198698,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "quadrature (0.3 rad)",
        "start",
        483605,
        Some(99.00),
        0.10,
        Some(141),
    ),
    (
        "quadrature (0.3 rad)",
        "mid-run",
        268509,
        Some(99.00),
        0.10,
        Some(0),
    ),
    ("acceleration step 1e5", "mid-run", 0, None, 0.10, None),
    (
        "acceleration step 1e6",
        "mid-run",
        1193,
        Some(99.00),
        0.10,
        Some(9),
    ),
    (
        "beyond the speed limit",
        "mid-run",
        1948,
        Some(99.00),
        0.10,
        Some(6),
    ),
    ("outliers", "mid-run", 2067, Some(99.00), 0.10, Some(1100)),
    ("NaN samples", "mid-run", 0, None, 0.10, None),
    ("resolver: healthy", "—", 0, None, 0.10, None),
    (
        "resolver: loss of excitation",
        "start",
        17721,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "resolver: loss of excitation",
        "mid-run",
        10179,
        Some(99.00),
        0.10,
        Some(1),
    ),
    (
        "resolver: brown-out (20 %)",
        "start",
        17766,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "resolver: brown-out (20 %)",
        "mid-run",
        9742,
        Some(99.00),
        0.10,
        Some(1),
    ),
    // A benign disturbance: its own flagged pairs are its false alarms, none today.
    (
        "resolver: carrier 2nd harmonic (15 %)",
        "start",
        0,
        None,
        0.10,
        None,
    ),
    (
        "resolver: carrier 2nd harmonic (15 %)",
        "mid-run",
        0,
        None,
        0.10,
        None,
    ),
    (
        "resolver: inverted excitation, excitation column",
        "start",
        0,
        None,
        0.10,
        None,
    ),
    (
        "resolver: inverted excitation, excitation column",
        "mid-run",
        0,
        None,
        0.10,
        None,
    ),
    // Revealed by the half-turn status alone: the pairs negated keep their offsets, which the
    // stored calibration (learned on the other half turn) doubles; at standstill the angle
    // stays off by about the bound, under the roundness check's reach.
    (
        "resolver: inverted excitation, no column, no delay stated",
        "start",
        1368,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "resolver: inverted excitation, no column, no delay stated",
        "mid-run",
        956,
        Some(99.00),
        0.10,
        Some(0),
    ),
    (
        "resolver: carrier delay 60 deg beyond the stated",
        "start",
        0,
        None,
        0.10,
        None,
    ),
    (
        "resolver: carrier delay 60 deg beyond the stated",
        "mid-run",
        14,
        Some(99.00),
        0.10,
        Some(1),
    ),
    (
        "resolver: dead winding",
        "start",
        35374,
        Some(99.00),
        0.10,
        Some(1),
    ),
    (
        "resolver: dead winding",
        "mid-run",
        23600,
        Some(99.00),
        0.10,
        Some(0),
    ),
];

/// The onset as the table writes it.
fn onset_label(row: &Row) -> &'static str {
    match row.onset {
        None => "—",
        Some(Onset::Start) => "start",
        Some(Onset::MidRun) => "mid-run",
    }
}

#[test]
fn fault_coverage_campaign() {
    let campaign = Campaign::run();
    let rows = campaign.rows();
    println!("BEGIN fault-coverage table");
    print!("{}", campaign.markdown());
    println!("END fault-coverage table");
    println!("the cases with the most wrong samples left unflagged:");
    for r in worst_cases(&campaign.results, 30) {
        println!(
            "  {:>6} of {:>6} wrong unflagged: {:?} from {:?}, {}, {}",
            r.wrong - r.wrong_flagged,
            r.wrong,
            r.case.fault,
            r.case.onset,
            r.case.speed.name(),
            r.case.setup.name(),
        );
    }
    let measured: Vec<&Row> = rows.iter().filter(|r| r.undetectable.is_none()).collect();
    assert_eq!(measured.len(), HELD.len(), "a row was added or lost");
    let mut unmet = 0;
    for row in &measured {
        let label = onset_label(row);
        let &(_, _, wrong, floor, ceiling, latency) = HELD
            .iter()
            .find(|h| h.0 == row.fault && h.1 == label)
            .unwrap_or_else(|| panic!("no figures held for {} ({label})", row.fault));
        let name = format!("{} ({label})", row.fault);
        // The faults still do what they did: as many wrong samples, within 10 %.
        assert!(
            row.wrong.abs_diff(wrong) * 10 <= wrong,
            "{name}: {} wrong samples, {wrong} held",
            row.wrong
        );
        match floor {
            Some(floor) => {
                let coverage = 100.0 * row.coverage.expect("wrong samples");
                assert!(
                    coverage >= floor,
                    "{name}: coverage {coverage:.2} % < {floor} %"
                );
            }
            None => assert_eq!(row.wrong, 0, "{name}"),
        }
        let false_alarms = 100.0 * row.false_alarms;
        assert!(
            false_alarms <= ceiling,
            "{name}: false alarms {false_alarms:.3} % > {ceiling} %"
        );
        // No fault latched on a healthy run: the target, met today.
        assert_eq!(row.latched_runs, 0, "{name}: latched on healthy runs");
        assert!(row.healthy_runs > 0, "{name}: no healthy twins");
        if let Some(ceiling) = latency {
            match row.latency {
                Latency::Samples(n) => assert!(n <= ceiling, "{name}: latency {n} > {ceiling}"),
                other => panic!("{name}: latency {other:?}, at most {ceiling} held"),
            }
        }
        let not_met = row.unmet_targets();
        if !not_met.is_empty() {
            unmet += 1;
            println!("target not yet met: {name}: {}", not_met.join(", "));
        }
    }
    // Without a stated delay every judged pair carries the half turn unresolved status (a
    // status: not flagged, not a false alarm); with one, or with the excitation's samples
    // while they are there, none of a healthy run's.
    for r in &campaign.results {
        let SensorKind::Resolver(kind) = r.case.setup.sensor else {
            continue;
        };
        let name = format!("{:?} on {}", r.case.fault, r.case.setup.name());
        if kind == ResolverKind::DelayNotStated {
            assert_eq!(r.half_turn_unresolved, r.samples, "{name}");
        } else if r.case.fault.is_healthy() {
            assert_eq!(r.half_turn_unresolved, 0, "{name}");
        }
    }
    println!(
        "{unmet} of {} rows below the issue's targets (coverage >= {} %, false alarms <= {} %, \
         nothing latched)",
        measured.len(),
        100.0 * COVERAGE_TARGET,
        100.0 * FALSE_ALARM_TARGET
    );
}

//! The campaign's figures per fault: coverage, false alarms on the healthy twins of its
//! cases, worst latency; as rows and as the Markdown table of `docs/guide/diagnostics.md`.

use std::fmt::Write;

use super::cases::{FaultKind, Onset};
use super::measurement::CaseResult;
use super::resolver;

/// The target for the coverage: at least 99 % of the wrong samples flagged.
pub const COVERAGE_TARGET: f64 = 0.99;

/// The target for the false alarms: at most 0.1 % of the healthy samples flagged
/// (and no fault latched on a healthy run none of whose samples was wrong).
pub const FALSE_ALARM_TARGET: f64 = 0.001;

/// The slowest first flag of a fault's cases that had wrong samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Latency {
    /// No case had a wrong sample: nothing to flag.
    NothingWrong,
    /// The most samples from an onset to its first flag.
    Samples(usize),
    /// Some case with wrong samples was never flagged.
    Never,
}

/// One fault (both channels of a channel fault together) at one onset, over every speed
/// and setup it was run on.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The fault's name.
    pub fault: &'static str,
    /// Its onset (`None` for the healthy baseline).
    pub onset: Option<Onset>,
    /// Cases run.
    pub cases: usize,
    /// Samples judged.
    pub samples: usize,
    /// Wrong samples (electrical angle error beyond the bound).
    pub wrong: usize,
    /// Wrong samples not flagged: what a user keeping the rows with no fault keeps.
    pub missed: usize,
    /// `wrong - missed` over `wrong`; `None` without a wrong sample.
    pub coverage: Option<f64>,
    /// Flagged samples over judged samples of the healthy runs of the same speeds and
    /// setups (of the row's own runs for a benign fault, [`FaultKind::is_benign`]).
    pub false_alarms: f64,
    /// Those healthy runs (the row's own runs for a benign fault).
    pub healthy_runs: usize,
    /// Those healthy runs that latched a fault after the start-up though none of their
    /// judged samples was wrong: a false latch. A healthy run whose loop's own transient
    /// was wrong (the instantaneous speed step) latches rightly, the flag of its wrong
    /// samples being the coverage the table counts.
    pub latched_runs: usize,
    /// The worst latency.
    pub latency: Latency,
    /// Why the fault is not measured, for the undetectable ones.
    pub undetectable: Option<&'static str>,
}

impl Row {
    /// The targets this row does not meet yet (empty: all met).
    pub fn unmet_targets(&self) -> Vec<&'static str> {
        let mut unmet = Vec::new();
        if self.undetectable.is_some() {
            return unmet;
        }
        if self.coverage.is_some_and(|c| c < COVERAGE_TARGET) {
            unmet.push("coverage < 99 %");
        }
        if self.false_alarms > FALSE_ALARM_TARGET {
            unmet.push("false alarms > 0.1 %");
        }
        if self.latched_runs > 0 {
            unmet.push("latched on healthy runs");
        }
        unmet
    }
}

/// The rows of `results`: the healthy baseline, each fault and onset in the campaign's
/// order, then each undetectable fault with its reason (the resolver's last).
pub fn rows(results: &[CaseResult]) -> Vec<Row> {
    let healthy: Vec<&CaseResult> = results
        .iter()
        .filter(|r| r.case.fault.is_healthy())
        .collect();
    let mut undetectable: Vec<(&'static str, &'static str)> = Vec::new();
    for fault in FaultKind::all() {
        if let Some(reason) = fault.undetectable()
            && !undetectable.iter().any(|(name, _)| *name == fault.name())
        {
            undetectable.push((fault.name(), reason));
        }
    }
    undetectable.extend(resolver::UNDETECTABLE);
    // The rows in the campaign's order (the results are in it), a row's onsets together:
    // each row's name and onset as its first case has them.
    let mut keys: Vec<(&'static str, Option<Onset>)> = Vec::new();
    for r in results {
        let onset = (!r.case.fault.is_healthy()).then_some(r.case.onset);
        if !keys.contains(&(r.case.row_name(), onset)) {
            keys.push((r.case.row_name(), onset));
        }
    }
    let first = |name: &str| keys.iter().position(|k| k.0 == name);
    let order: Vec<Option<usize>> = keys.iter().map(|k| first(k.0)).collect();
    let mut keyed: Vec<_> = order.into_iter().zip(keys).collect();
    keyed.sort_by_key(|(first, _)| *first);
    let keys = keyed.into_iter().map(|(_, key)| key);
    let mut rows: Vec<Row> = keys
        .into_iter()
        .map(|(name, onset)| {
            let of_row: Vec<&CaseResult> = results
                .iter()
                .filter(|r| {
                    r.case.row_name() == name && (onset.is_none() || onset == Some(r.case.onset))
                })
                .collect();
            // The healthy twins: the same speed and setup, no fault. A benign fault must not
            // be flagged: its own runs are its twins.
            let benign = of_row.iter().any(|r| r.case.fault.is_benign());
            let twins: Vec<&CaseResult> = if benign {
                of_row.clone()
            } else {
                healthy
                    .iter()
                    .copied()
                    .filter(|h| {
                        of_row
                            .iter()
                            .any(|r| r.case.speed == h.case.speed && r.case.setup == h.case.setup)
                    })
                    .collect()
            };
            let sum = |f: &dyn Fn(&CaseResult) -> usize| of_row.iter().map(|r| f(r)).sum::<usize>();
            let wrong = sum(&|r| r.wrong);
            let missed = wrong - sum(&|r| r.wrong_flagged);
            let twin_samples: usize = twins.iter().map(|h| h.samples).sum();
            let twin_flagged: usize = twins.iter().map(|h| h.flagged).sum();
            let with_wrong = of_row.iter().filter(|r| r.wrong > 0);
            // The healthy runs have no onset: nothing to be late for.
            let latency = if wrong == 0 || onset.is_none() {
                Latency::NothingWrong
            } else if with_wrong.clone().any(|r| r.latency.is_none()) {
                Latency::Never
            } else {
                Latency::Samples(with_wrong.filter_map(|r| r.latency).max().unwrap_or(0))
            };
            Row {
                fault: name,
                onset,
                cases: of_row.len(),
                samples: sum(&|r| r.samples),
                wrong,
                missed,
                coverage: (wrong > 0).then(|| (wrong - missed) as f64 / wrong as f64),
                false_alarms: twin_flagged as f64 / twin_samples.max(1) as f64,
                healthy_runs: twins.len(),
                latched_runs: twins.iter().filter(|h| h.latched && h.wrong == 0).count(),
                latency,
                undetectable: None,
            }
        })
        .collect();
    rows.extend(undetectable.into_iter().map(|(fault, reason)| Row {
        fault,
        onset: None,
        cases: 0,
        samples: 0,
        wrong: 0,
        missed: 0,
        coverage: None,
        false_alarms: 0.0,
        healthy_runs: 0,
        latched_runs: 0,
        latency: Latency::NothingWrong,
        undetectable: Some(reason),
    }));
    rows
}

/// A fraction as a percentage with two decimals.
fn percent(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// `rows` as a Markdown table, each row's unmet targets named beside it.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::new();
    out.push_str(
        "| fault | onset | cases | samples | wrong | coverage | missed | false alarms \
         | latched healthy runs | worst latency | targets |\n",
    );
    out.push_str("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |\n");
    for row in rows {
        if let Some(reason) = row.undetectable {
            let _ = writeln!(
                out,
                "| {} | both | — | — | — | undetectable | — | — | — | — | not counted: {reason} |",
                row.fault
            );
            continue;
        }
        let onset = match row.onset {
            None => "—",
            Some(Onset::Start) => "start",
            Some(Onset::MidRun) => "mid-run",
        };
        let coverage = row.coverage.map_or("— (none wrong)".to_string(), percent);
        let latency = match row.latency {
            Latency::NothingWrong => "—".to_string(),
            Latency::Samples(n) => n.to_string(),
            Latency::Never => "never".to_string(),
        };
        let unmet = row.unmet_targets();
        let targets = if unmet.is_empty() {
            "met".to_string()
        } else {
            format!("not yet: {}", unmet.join(", "))
        };
        let _ = writeln!(
            out,
            "| {} | {onset} | {} | {} | {} | {coverage} | {} | {} | {} of {} | {latency} | {targets} |",
            row.fault,
            row.cases,
            row.samples,
            row.wrong,
            row.missed,
            percent(row.false_alarms),
            row.latched_runs,
            row.healthy_runs,
        );
    }
    out
}

/// The `n` cases with the most wrong samples left unflagged, most first: where the gaps
/// are.
pub fn worst_cases(results: &[CaseResult], n: usize) -> Vec<&CaseResult> {
    let mut sorted: Vec<&CaseResult> = results
        .iter()
        .filter(|r| r.wrong > r.wrong_flagged)
        .collect();
    sorted.sort_by_key(|r| std::cmp::Reverse(r.wrong - r.wrong_flagged));
    sorted.truncate(n);
    sorted
}

//! `lumiere stress`: the numerical stress suite and its table.

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};

use lumiere::course::Choice;
use lumiere::tools::stress::{Case, Effort, table};

use super::Failure;

/// The arguments of `lumiere stress`.
#[derive(Args)]
pub struct StressArgs {
    /// The test suite's sizes (seconds) instead of the full figures (10^6 rays and samples).
    #[arg(long)]
    quick: bool,
    /// Run only these cases (comma-separated; default: all).
    #[arg(long, value_delimiter = ',')]
    only: Vec<Case>,
}

/// Runs the cases, prints the table; fails (exit code 1) if any case failed.
pub fn run(args: &StressArgs) -> Result<(), Failure> {
    let effort = if args.quick {
        Effort::Quick
    } else {
        Effort::Full
    };
    let cases: Vec<Case> = if args.only.is_empty() {
        Case::all()
    } else {
        args.only.clone()
    };
    let bar = ProgressBar::new(cases.len() as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}").expect("a valid template"),
    );
    let mut reports = Vec::new();
    for case in cases {
        bar.set_message(format!("{case}: {}", case.description()));
        reports.push(case.run(effort));
        bar.inc(1);
    }
    bar.finish_and_clear();
    print!("{}", table(&reports));
    let failed = reports.iter().filter(|r| !r.passed()).count();
    if failed > 0 {
        return Err(Failure::runtime(anyhow::anyhow!(
            "{failed} of {} stress cases failed",
            reports.len()
        )));
    }
    println!("all {} cases passed", reports.len());
    Ok(())
}

//! The numerical stress suite at the test suite's size: no NaN, infinite or
//! negative sample reaches the film, no ray leaks out of a closed scene, and
//! every known energy comes back within the noise (`src/tools/stress/`).

use lumiere::course::Choice;
use lumiere::tools::stress::{Case, Effort, table};

#[test]
fn every_stress_case_passes_without_invalid_samples_or_leaks() {
    let reports: Vec<_> = Case::all()
        .into_iter()
        .map(|c| c.run(Effort::Quick))
        .collect();
    let printed = table(&reports);
    for report in &reports {
        assert_eq!(report.invalid_samples, 0, "{printed}");
        assert_eq!(report.leaked_rays, 0, "{printed}");
        assert!(report.passed(), "{printed}");
        assert!(report.samples > 0 && report.variants > 0, "{printed}");
    }
    // the cases with a closed form measured it
    for case in [
        Case::TinyScale,
        Case::WhiteFurnace,
        Case::MirrorCorridor,
        Case::Grazing,
        Case::GlassBall,
    ] {
        let report = reports.iter().find(|r| r.case == case).unwrap();
        assert!(report.energy_error.is_some(), "{case}: {printed}");
    }
}

#[test]
fn the_suite_notices_what_it_checks() {
    use lumiere::tools::stress::term_mean;
    // a term's mean over a film that holds nothing is zero, not NaN
    let film = lumiere::Film::new(2, 2);
    let mean = term_mean(&film, lumiere::Term::L1, |_| true);
    assert_eq!((mean.value, mean.standard_error), (0.0, 0.0));
    // unknown case names are refused with the list
    let error = "nope".parse::<Case>().unwrap_err();
    assert!(error.contains("white-furnace"), "{error}");
}

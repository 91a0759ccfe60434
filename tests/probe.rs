//! The pixel probe traces again exactly the samples the film summed: same
//! streams, same pass indices, even when a term skipped passes.

mod common;

use lumiere::analysis::probe::{MAX_PROBE_SAMPLES, probe_pixel};
use lumiere::render::{PassBuffer, render_pass};
use lumiere::scene::builtin;
use lumiere::{Film, RenderContext, RenderSettings, Term, TermSet};

#[test]
fn probe_reproduces_the_film_mean_and_error_after_a_term_was_hidden() {
    let settings = RenderSettings {
        width: 24,
        height: 18,
        terms: TermSet::ALL,
        ..RenderSettings::default()
    };
    let mut context = RenderContext::new(builtin::cornell(), settings);
    let mut film = Film::new(24, 18);
    let mut buffer = PassBuffer::default();
    // passes 0–5 with all terms, 6–9 without L2, 10–15 with all again
    for pass in 0..16 {
        context.settings.terms = if (6..10).contains(&pass) {
            TermSet::ALL.with(Term::L2, false)
        } else {
            TermSet::ALL
        };
        let counts = render_pass(&context, &mut film, pass, &mut buffer);
        common::assert_no_invalid_samples(&counts);
    }
    context.settings.terms = TermSet::ALL;
    assert_eq!(film.samples(Term::L1), 16);
    assert_eq!(film.samples(Term::L2), 12);

    let mut checked = 0;
    for (x, y) in [(12, 2), (3, 9), (20, 15), (12, 9), (0, 0)] {
        let probe = probe_pixel(&context, &film, x, y, TermSet::ALL, MAX_PROBE_SAMPLES);
        assert_eq!(probe.terms.len(), 4);
        let pixel = (y * 24 + x) as usize;
        for term in &probe.terms {
            let stored = film.term(term.term).unwrap();
            assert_eq!(term.samples.len() as u32, stored.samples);
            // the same samples added in the same order: bit-identical sums
            assert_eq!(
                term.mean,
                stored.mean(pixel),
                "{:?} at ({x}, {y})",
                term.term
            );
            assert_eq!(term.standard_error, stored.standard_error(pixel));
            assert!((term.mean_luminance() - stored.luminance[pixel].mean).abs() < 1e-12);
            assert!(term.reproduces_film());
            if term.standard_error > 0.0 {
                checked += 1;
            }
        }
    }
    assert!(checked >= 8, "too few noisy pixels to compare ({checked})");
}

#[test]
fn probe_caps_the_samples_it_traces_and_says_so() {
    let settings = RenderSettings {
        width: 8,
        height: 6,
        terms: TermSet::COURSE,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(builtin::cornell(), settings);
    let mut film = Film::new(8, 6);
    let mut buffer = PassBuffer::default();
    for pass in 0..12 {
        let counts = render_pass(&context, &mut film, pass, &mut buffer);
        common::assert_no_invalid_samples(&counts);
    }
    let probe = probe_pixel(&context, &film, 4, 3, TermSet::only(Term::L1), 5);
    let l1 = &probe.terms[0];
    assert_eq!((l1.samples.len(), l1.film_samples), (5, 12));
    assert!(!l1.is_complete() && !l1.reproduces_film());
}

//! `lumiere lessons`: the built-in lessons and scenes.

use clap::Args;

use lumiere::lesson::{BUILTIN, Lang, Lesson};
use lumiere::scene::builtin;

use super::Failure;

/// The arguments of `lumiere lessons`.
#[derive(Args)]
pub struct LessonsArgs {
    /// The language of the titles: fr or en.
    #[arg(long, default_value = "en")]
    lang: Lang,
}

/// Prints each built-in lesson (name, title, steps) and each built-in scene.
pub fn run(args: &LessonsArgs) -> Result<(), Failure> {
    println!("lessons (lumiere view --lesson NAME [--step N] [--lang fr|en]):");
    for (name, _) in BUILTIN {
        let lesson = Lesson::load(name).map_err(Failure::runtime)?;
        println!(
            "  {name:<22} {} ({} steps)",
            lesson.title.get(args.lang),
            lesson.steps.len()
        );
        for (i, step) in lesson.steps.iter().enumerate() {
            println!("    {:>2}. {}", i + 1, step.title.get(args.lang));
        }
    }
    println!("scenes (lumiere view SCENE, lumiere render SCENE):");
    for scene in &builtin::SCENES {
        println!("  {:<22} {}", scene.name, scene.description);
    }
    Ok(())
}

//! `project::job::post_job` (the workstation's "Post job…"): every setup with operations gets
//! one program, in the setup's work offset, that reads back through Talas's interpreter, and
//! it is the program `post_setup` makes of the setup's own plans linked by `link_setup` (one
//! route with `talas job --post`, not two).

use std::path::Path;

use talas::diagnostics::Progress;
use talas::import::{OpenOptions, open};
use talas::project::Project;
use talas::project::job::{link_setup, plan_in_setup, post_job, post_setup};

fn job() -> (Project, talas::import::Workpiece) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/job");
    let project = Project::load(&dir.join("plate-job.talas")).expect("the job reads");
    let part = open(
        &dir.join("../plate-hole.stp"),
        &OpenOptions::default(),
        &Progress::new(),
    )
    .expect("the part reads");
    (project, part)
}

#[test]
fn the_job_posts_one_program_per_setup_in_its_work_offset() {
    let (project, part) = job();
    let programs = post_job(&project, &part, &Progress::new()).expect("the job posts");
    assert_eq!(programs.len(), project.setups.len());
    for p in &programs {
        let setup = &project.setups[p.setup];
        assert!(
            p.stem.starts_with(&format!("{:02}-", p.setup + 1)),
            "{}",
            p.stem
        );
        let code = setup.frame.work_offset_code();
        assert!(
            p.program.text.lines().any(|l| l.contains(code.as_str())),
            "setup '{}' is posted under {code}",
            setup.name
        );
        // The same program as the setup's own plans posted directly.
        let paths: Vec<_> = setup
            .operations
            .iter()
            .map(|&op| {
                plan_in_setup(&project, op, &part, &Progress::new())
                    .expect("plans")
                    .toolpath
            })
            .collect();
        let (linked, _) =
            link_setup(&project, p.setup, &part, &paths, false, &Progress::new()).expect("links");
        let linked: Vec<_> = linked.into_iter().map(|l| l.toolpath).collect();
        let direct = post_setup(&project, p.setup, &linked).expect("posts");
        assert_eq!(direct.text, p.program.text, "deterministic, one route");
        // It reads back.
        let read = talas::gcode::interpret(&p.program.text, &Default::default());
        assert!(read.is_ok(), "setup '{}': {:?}", setup.name, read.err());
    }
}

#[test]
fn a_cancelled_job_posts_nothing() {
    let (project, part) = job();
    let progress = Progress::new();
    progress.cancel();
    let e = post_job(&project, &part, &progress).expect_err("cancelled");
    assert_eq!(e, "cancelled");
}

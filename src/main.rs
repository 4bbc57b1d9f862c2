//! The `talas` binary: parse the command line, then run a subcommand or the workstation.

use clap::Parser;
use talas::cli::{self, Args};

/// The process's allocator: mimalloc keeps freed pages for reuse, where glibc's malloc gives a
/// plan's tens of MB back to the kernel and faults them in again on the next plan (about a
/// fifth of the CPU time of blended feed planning; benches/README.md, feed section).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let args = Args::parse();
    // The setup sheet's pictures come from the workstation's offscreen renderer when there is
    // one (else the engine draws them in software).
    #[cfg(feature = "gui")]
    talas::project::sheet::set_drawer(talas::app::offscreen_render::sheet_picture);
    let code = match args.command {
        #[cfg(feature = "gui")]
        Some(cli::Command::Render(render)) => talas::app::offscreen_render::run(&render),
        Some(command) => cli::run(command),
        None => open_workstation(args.file),
    };
    std::process::exit(code);
}

#[cfg(feature = "gui")]
fn open_workstation(file: Option<std::path::PathBuf>) -> i32 {
    match talas::app::run(file) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("talas: {e}");
            cli::EXIT_INTERNAL
        }
    }
}

#[cfg(not(feature = "gui"))]
fn open_workstation(_file: Option<std::path::PathBuf>) -> i32 {
    eprintln!(
        "talas: this build has no workstation (built without the `gui` feature); see `talas --help`"
    );
    cli::EXIT_BAD_INPUT
}

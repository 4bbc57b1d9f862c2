//! `talas render FILE [--path PATH.json] [--width W --height H] -o VIEW.png`: the workstation's
//! renderer, offscreen. The drawing itself lives with the workstation (`app::offscreen_render`,
//! feature `gui`); the binary sends this command there, and a build without the renderer
//! answers with one line on stderr.

use std::path::PathBuf;

/// Options of `talas render`.
#[derive(Clone, Debug, clap::Args)]
pub struct RenderArgs {
    /// The part (STEP or STL).
    pub file: PathBuf,
    /// A tool path (the contract's Tool path JSON) drawn over the part, coloured by move kind.
    #[arg(long, value_name = "PATH.json")]
    pub path: Option<PathBuf>,
    /// Image width, pixels.
    #[arg(long, value_name = "PX", default_value_t = 1600)]
    pub width: u32,
    /// Image height, pixels.
    #[arg(long, value_name = "PX", default_value_t = 1000)]
    pub height: u32,
    /// The PNG to write.
    #[arg(short = 'o', long = "output", value_name = "VIEW.png")]
    pub output: PathBuf,
    /// View direction: iso, top, front, right, back, left or bottom.
    #[arg(long, value_name = "VIEW", default_value = "iso")]
    pub view: String,
    /// Colour the part by a scalar field: none, k-min, k-max or mean (curvature, 1/mm).
    #[arg(long, value_name = "FIELD", default_value = "none")]
    pub colour_by: String,
    /// Do not draw the part's feature edges.
    #[arg(long)]
    pub no_edges: bool,
    /// Do not draw the ground grid.
    #[arg(long)]
    pub no_grid: bool,
    /// Orthographic instead of perspective projection.
    #[arg(long)]
    pub ortho: bool,
}

/// Largest image side accepted, pixels.
pub const MAX_SIDE_PX: u32 = 8192;

impl RenderArgs {
    /// Check the sizes.
    ///
    /// # Errors
    /// A one-line message for a zero or too large width or height.
    pub fn check_size(&self) -> Result<(), String> {
        for (what, v) in [("width", self.width), ("height", self.height)] {
            if v == 0 || v > MAX_SIDE_PX {
                return Err(format!(
                    "--{what} {v}: must be between 1 and {MAX_SIDE_PX} pixels"
                ));
            }
        }
        Ok(())
    }
}

/// The answer of a build without the renderer (no `gui` feature).
#[must_use]
pub fn unavailable() -> i32 {
    eprintln!(
        "talas render: this build has no renderer (built without the `gui` feature); rebuild with default features"
    );
    super::EXIT_BAD_INPUT
}

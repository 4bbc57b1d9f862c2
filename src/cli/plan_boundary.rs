//! `talas plan … --boundary`: a planned 3-axis finishing path limited to a drawn polygon or the
//! part's silhouette ([`crate::strategies::boundary`]), with a note of what was kept.

use crate::diagnostics::Diagnostic;
use crate::import::ImportError;
use crate::import::workpiece::Workpiece;
use crate::project::pipeline::Computed;
use crate::strategies::boundary::{Boundary, BoundaryRule, limit};

/// `computed` limited to the boundary given by `text` under `rule`.
///
/// # Errors
/// A bad boundary text, or a rule the path cannot be tested by, naming `--boundary`.
pub fn limit_computed(
    part: &Workpiece,
    mut computed: Computed,
    text: &str,
    rule: BoundaryRule,
) -> Result<Computed, ImportError> {
    let bad = |msg: String| ImportError::new(&part.source, Some("--boundary".into()), msg);
    let boundary = Boundary::parse(text, rule).map_err(bad)?;
    let bvh = part.bvh().map_err(bad)?;
    let (tp, report) = limit(&computed.toolpath, &bvh, &boundary).map_err(bad)?;
    if report.pieces == 0 {
        return Err(bad(
            "no cutting move of the path lies inside the boundary".into()
        ));
    }
    computed.diagnostics.push(Diagnostic::info(
        None,
        format!(
            "boundary: {} cutting pieces kept, {} cutting poses outside removed",
            report.pieces, report.removed
        ),
    ));
    computed.toolpath = tp;
    computed.passes = report.pieces;
    Ok(computed)
}

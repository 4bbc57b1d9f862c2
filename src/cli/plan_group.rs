//! `talas plan --face A,B,C`: one finishing operation over a face group
//! ([`crate::strategies::finish::group::plan_group`]), written and reported as `talas plan` writes one
//! face's path.

use serde_json::{Value, json};

use super::plan::{PlanArgs, whole_part};
use crate::checks::part::PartCheck;
use crate::geometry::brep::Part;
use crate::import::ImportError;
use crate::strategies::finish::group::plan_group;
use crate::strategies::finish::tiltaway::{PartContext, TiltAway};
use crate::strategies::finish::{FinishOptions, Strategy};
use crate::tools::Cutter;

/// Plan the group `args.face`, save the joined path, and build the JSON report.
///
/// # Errors
/// An [`ImportError`] naming the file and the face that failed.
pub fn plan_group_cli(
    args: &PlanArgs,
    part: &Part,
    cutter: &Cutter,
    strategy: Strategy,
    opts: &FinishOptions,
) -> Result<Value, ImportError> {
    let whole = if args.check || args.tilt_away.is_some() {
        Some(whole_part(args, part)?)
    } else {
        None
    };
    let context = whole.as_ref().map(|(wp, bvh)| PartContext {
        check: PartCheck::of_workpiece(wp, bvh, &args.face),
        tilt: args.tilt_away.map(|deg| TiltAway {
            max_angle_rad: deg.to_radians(),
            max_from_vertical_rad: args.max_tilt.to_radians(),
            steep_angle_rad: args.steep_tilt.to_radians(),
            ..TiltAway::default()
        }),
    });
    let r = plan_group(
        part,
        &args.face,
        cutter,
        &crate::tools::tool_spec(cutter),
        strategy,
        opts,
        context.as_ref(),
    )
    .map_err(|(k, e)| {
        let source = part.faces.get(k).map_or(0, |f| f.source_id);
        ImportError::new(
            &args.file,
            Some(format!("face {k} (#{source})")),
            e.to_string(),
        )
    })?;
    r.toolpath
        .save(&args.output)
        .map_err(|e| ImportError::new(&args.output, Some(e.place.clone()), e.message.clone()))?;
    Ok(json!({
        "file": args.file.display().to_string(),
        "output": args.output.display().to_string(),
        "faces": args.face,
        "strategy": args.strategy,
        "tool": args.tool,
        "summary": r.toolpath.summary,
        "passes": r.passes,
        "clearance_mm": r.clearance,
        "diagnostics": r.diagnostics,
        "part_hits": r.part_hits,
        "left_out": r.left_out,
    }))
}

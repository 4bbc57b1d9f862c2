//! The command line's tool SPEC: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`,
//! `cone:d=10,angle=45` (half-angle in degrees), each optionally followed by `,flute=20`,
//! `,shank=8`, `,length=60` (overall) and `,holder=DxL+DxL` (holder cylinders, bottom up), and
//! for the cutting-force model `,flutes=N`, `,helix=DEG`, `,rake=DEG` (any of them given makes
//! the cutter carry [`Flutes`]; helix defaults to 30°, rake to 0°, flutes must be given).

use super::{Cutter, CutterKind, Flutes, HolderSection, ToolError};

/// Parse a tool SPEC into a validated [`Cutter`].
///
/// # Errors
/// [`ToolError::Spec`] for an unknown kind or key, a missing `d` (or `r`, `angle`), a repeated
/// key or a value that is not a number; [`ToolError::Dimension`] for sizes that are out of range.
pub fn parse_tool_spec(spec: &str) -> Result<Cutter, ToolError> {
    let err = |message: String| ToolError::Spec {
        spec: spec.to_string(),
        message,
    };
    let (kind, rest) = spec.trim().split_once(':').ok_or_else(|| {
        err("expected KIND:d=DIAMETER,... (kinds: ball, flat, bull, cone)".into())
    })?;
    let mut fields: Vec<(&str, &str)> = Vec::new();
    for part in rest.split(',') {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| err(format!("'{part}' is not KEY=VALUE")))?;
        let k = k.trim();
        if fields.iter().any(|(seen, _)| *seen == k) {
            return Err(err(format!("key '{k}' given twice")));
        }
        fields.push((k, v.trim()));
    }
    let allowed: &[&str] = match kind.trim() {
        "ball" | "flat" => &[
            "d", "flute", "shank", "length", "holder", "flutes", "helix", "rake",
        ],
        "bull" => &[
            "d", "r", "flute", "shank", "length", "holder", "flutes", "helix", "rake",
        ],
        "cone" => &[
            "d", "angle", "flute", "shank", "length", "holder", "flutes", "helix", "rake",
        ],
        other => {
            return Err(err(format!(
                "unknown tool kind '{other}' (kinds: ball, flat, bull, cone)"
            )));
        }
    };
    if let Some((k, _)) = fields.iter().find(|(k, _)| !allowed.contains(k)) {
        return Err(err(format!(
            "unknown key '{k}' for a {kind} cutter (keys: {})",
            allowed.join(", ")
        )));
    }
    let number = |key: &str| -> Result<Option<f64>, ToolError> {
        match fields.iter().find(|(k, _)| *k == key) {
            None => Ok(None),
            Some((_, v)) => v
                .parse::<f64>()
                .map(Some)
                .map_err(|_| err(format!("{key}={v} is not a number"))),
        }
    };
    let need = |key: &str| -> Result<f64, ToolError> {
        number(key)?.ok_or_else(|| err(format!("missing {key}=")))
    };
    let kind = match kind.trim() {
        "ball" => CutterKind::Ball,
        "flat" => CutterKind::Flat,
        "bull" => CutterKind::BullNose {
            corner_radius: need("r")?,
        },
        _ => CutterKind::Cone {
            half_angle: need("angle")?.to_radians(),
        },
    };
    let mut cutter = Cutter::new(kind, need("d")?)?;
    if let Some(f) = number("flute")? {
        cutter.flute_length = f;
        cutter.overall_length = cutter.overall_length.max(f + cutter.diameter);
    }
    if let Some(s) = number("shank")? {
        cutter.shank_diameter = s;
    }
    if let Some(l) = number("length")? {
        cutter.overall_length = l;
    }
    if let Some((_, h)) = fields.iter().find(|(k, _)| *k == "holder") {
        cutter.holder = parse_holder(h).map_err(err)?;
    }
    cutter.flutes = parse_flutes(&number)?;
    if cutter.flutes.is_some() && matches!(cutter.kind, CutterKind::Cone { .. }) {
        return Err(err(
            "flutes=, helix=, rake= are for flat, ball and bull cutters".into(),
        ));
    }
    cutter.validate()?;
    Ok(cutter)
}

/// `flutes=N,helix=DEG,rake=DEG` into [`Flutes`]; `None` when none of them is given.
fn parse_flutes(
    number: &dyn Fn(&str) -> Result<Option<f64>, ToolError>,
) -> Result<Option<Flutes>, ToolError> {
    let (count, helix, rake) = (number("flutes")?, number("helix")?, number("rake")?);
    if count.is_none() && helix.is_none() && rake.is_none() {
        return Ok(None);
    }
    let count = count.ok_or_else(|| {
        ToolError::Dimension("helix= or rake= needs flutes=N (the number of flutes)".into())
    })?;
    if !(count.fract() == 0.0 && (1.0..=16.0).contains(&count)) {
        return Err(ToolError::Dimension(format!(
            "flutes must be a whole number from 1 to 16, got {count}"
        )));
    }
    let flutes = Flutes {
        // Exact: a whole number in 1..=16.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        count: count as u32,
        helix: helix.map_or(Flutes::DEFAULT_HELIX, f64::to_radians),
        rake: rake.unwrap_or(0.0).to_radians(),
    };
    flutes.validate()?;
    Ok(Some(flutes))
}

/// `angle_rad` in degrees as a spec writes it: the shortest decimal (to 1e-9°) that reads
/// back to the same angle, so 59° stays `59`, not `59.00000000000001`.
fn degrees(angle_rad: f64) -> f64 {
    let exact = angle_rad.to_degrees();
    let rounded = (exact * 1e9).round() / 1e9;
    if rounded.to_radians() == angle_rad {
        rounded
    } else {
        exact
    }
}

/// The spec string of `cutter` (`bull:d=10,r=2,flute=20,shank=10,length=70,holder=40x60`):
/// every size written, so [`parse_tool_spec`] gives the same cutter back.
#[must_use]
pub fn tool_spec(cutter: &Cutter) -> String {
    let mut s = match cutter.kind {
        CutterKind::Ball => format!("ball:d={}", cutter.diameter),
        CutterKind::Flat => format!("flat:d={}", cutter.diameter),
        CutterKind::BullNose { corner_radius } => {
            format!("bull:d={},r={corner_radius}", cutter.diameter)
        }
        CutterKind::Cone { half_angle } => {
            format!("cone:d={},angle={}", cutter.diameter, degrees(half_angle))
        }
    };
    s.push_str(&format!(
        ",flute={},shank={},length={}",
        cutter.flute_length, cutter.shank_diameter, cutter.overall_length
    ));
    if !cutter.holder.is_empty() {
        let sections: Vec<String> = cutter
            .holder
            .iter()
            .map(|h| format!("{}x{}", h.diameter, h.length))
            .collect();
        s.push_str(&format!(",holder={}", sections.join("+")));
    }
    if let Some(f) = &cutter.flutes {
        s.push_str(&format!(
            ",flutes={},helix={},rake={}",
            f.count,
            f.helix.to_degrees(),
            f.rake.to_degrees()
        ));
    }
    s
}

fn parse_holder(text: &str) -> Result<Vec<HolderSection>, String> {
    text.split('+')
        .map(|s| {
            let (d, l) = s
                .split_once('x')
                .ok_or_else(|| format!("holder section '{s}' is not DIAMETERxLENGTH"))?;
            let num = |v: &str| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| format!("holder section '{s}': '{v}' is not a number"))
            };
            Ok(HolderSection {
                diameter: num(d)?,
                length: num(l)?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contract_specs() {
        let b = parse_tool_spec("ball:d=6").expect("ball");
        assert_eq!(b.kind, CutterKind::Ball);
        assert!((b.radius() - 3.0).abs() < 1e-15);
        let f = parse_tool_spec("flat:d=10,flute=20,shank=8").expect("flat");
        assert_eq!(f.flute_length, 20.0);
        assert_eq!(f.shank_diameter, 8.0);
        let u = parse_tool_spec("bull:d=10,r=2").expect("bull");
        assert_eq!(u.kind, CutterKind::BullNose { corner_radius: 2.0 });
        let c = parse_tool_spec("cone:d=10,angle=45,holder=20x30+40x50").expect("cone");
        assert!((c.profile_height() - 5.0).abs() < 1e-12);
        assert_eq!(c.holder.len(), 2);
    }

    #[test]
    fn spec_round_trips() {
        for spec in [
            "ball:d=6",
            "flat:d=10,flute=20,shank=8",
            "bull:d=10,r=2,holder=20x30+40x50",
            "cone:d=10,angle=30,length=55",
        ] {
            let c = parse_tool_spec(spec).expect(spec);
            let written = tool_spec(&c);
            let back = parse_tool_spec(&written).expect(&written);
            let same_kind = match (back.kind, c.kind) {
                (CutterKind::Cone { half_angle: a }, CutterKind::Cone { half_angle: b }) => {
                    (a - b).abs() < 1e-12
                }
                (a, b) => a == b,
            };
            assert!(same_kind, "{written}");
            assert!((back.diameter - c.diameter).abs() < 1e-12, "{written}");
            assert_eq!(back.flute_length, c.flute_length, "{written}");
            assert_eq!(back.shank_diameter, c.shank_diameter, "{written}");
            assert_eq!(back.overall_length, c.overall_length, "{written}");
            assert_eq!(back.holder, c.holder, "{written}");
            assert_eq!(back.flutes, None, "{written}");
            assert!(!written.contains("flutes"), "{written}");
        }
    }

    #[test]
    fn angles_are_written_as_typed() {
        // 59.to_radians().to_degrees() is 59.00000000000001: the spec must say 59.
        for (spec, angle) in [
            ("cone:d=10,angle=59", "angle=59,"),
            ("cone:d=3,angle=45", "angle=45,"),
        ] {
            let written = tool_spec(&parse_tool_spec(spec).expect(spec));
            assert!(written.contains(angle), "{written}");
        }
        // An angle with no short decimal keeps its exact digits (it reads back the same).
        let odd = Cutter {
            kind: CutterKind::Cone {
                half_angle: 0.823_456_789_012_345_6,
            },
            ..parse_tool_spec("cone:d=10,angle=30").expect("cone")
        };
        let written = tool_spec(&odd);
        let back = parse_tool_spec(&written).expect("written");
        let CutterKind::Cone { half_angle } = back.kind else {
            panic!("{written}")
        };
        assert!(
            (half_angle - 0.823_456_789_012_345_6).abs() < 1e-15,
            "{written}"
        );
    }

    #[test]
    fn flute_geometry() {
        let c = parse_tool_spec("flat:d=12,flutes=2,helix=30,rake=15").expect("flat");
        let f = c.flutes.expect("flutes");
        assert_eq!(f.count, 2);
        assert!((f.helix - 30f64.to_radians()).abs() < 1e-15);
        assert!((f.rake - 15f64.to_radians()).abs() < 1e-15);
        let back = parse_tool_spec(&tool_spec(&c)).expect("round trip");
        let g = back.flutes.expect("flutes back");
        assert_eq!(g.count, 2);
        assert!((g.helix - f.helix).abs() < 1e-12 && (g.rake - f.rake).abs() < 1e-12);
        let d = parse_tool_spec("ball:d=6,flutes=3").expect("defaults");
        let f = d.flutes.expect("flutes");
        assert!((f.helix - 30f64.to_radians()).abs() < 1e-15 && f.rake == 0.0);
        for bad in [
            "flat:d=12,helix=30",
            "flat:d=12,flutes=2.5",
            "flat:d=12,flutes=0",
            "flat:d=12,flutes=2,helix=70",
            "flat:d=12,flutes=2,rake=50",
            "cone:d=10,angle=45,flutes=2",
        ] {
            assert!(parse_tool_spec(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn errors_are_clear() {
        for bad in [
            "ball",
            "ball:d=x",
            "drill:d=3",
            "ball:d=6,r=1",
            "bull:d=10",
            "bull:d=10,r=6",
            "ball:d=6,d=7",
            "ball:d=-6",
            "flat:d=10,flute=0",
            "cone:d=10,angle=95",
            "ball:d=6,holder=20",
        ] {
            let e = parse_tool_spec(bad).expect_err(bad);
            assert!(!e.to_string().is_empty());
        }
    }
}

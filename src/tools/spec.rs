//! The command line's tool SPEC: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`,
//! `cone:d=10,angle=45` (half-angle in degrees), each optionally followed by `,flute=20`,
//! `,shank=8`, `,length=60` (overall) and `,holder=DxL+DxL` (holder cylinders, bottom up).

use super::{Cutter, CutterKind, HolderSection, ToolError};

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
        "ball" | "flat" => &["d", "flute", "shank", "length", "holder"],
        "bull" => &["d", "r", "flute", "shank", "length", "holder"],
        "cone" => &["d", "angle", "flute", "shank", "length", "holder"],
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
    cutter.validate()?;
    Ok(cutter)
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
            format!(
                "cone:d={},angle={}",
                cutter.diameter,
                half_angle.to_degrees()
            )
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

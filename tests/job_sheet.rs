//! The job's setup sheet (issue 31): `talas job tests/data/job/job-part.talas --sheet
//! OUT.html` writes one self-contained HTML file (no script, no outside reference) with the
//! tools and, per setup, an embedded PNG picture of the part, stock and workholding with the
//! work offset's axes, the stock size and the operations with feeds, speeds, heights, time at
//! feed and the jerk-limited cycle time. Checked against the job's own JSON (`--json`), against
//! the project file, and by decoding each picture (its size, and that the part covers a fair
//! share of it); the same job writes the same bytes twice. A vise holds the first setup.

use std::path::PathBuf;
use std::process::Command;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn run_sheet(project: &std::path::Path, out: &std::path::Path) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_talas"))
        .arg("job")
        .arg(project)
        .arg("--part")
        .arg(data("job/job-part.stp"))
        .arg("--sheet")
        .arg(out)
        .arg("--json")
        .output()
        .expect("talas runs");
    assert!(
        o.status.success(),
        "talas job failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("JSON")
}

/// The embedded pictures: base64 PNG data of each `<image>`.
fn pictures(html: &str) -> Vec<Vec<u8>> {
    html.split("href=\"data:image/png;base64,")
        .skip(1)
        .map(|rest| {
            let b64 = &rest[..rest.find('"').expect("closing quote")];
            decode64(b64)
        })
        .collect()
}

/// Base64 decoding written from RFC 4648 (independent of the encoder under test).
fn decode64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => u32::from(c - b'A'),
            b'a'..=b'z' => u32::from(c - b'a') + 26,
            b'0'..=b'9' => u32::from(c - b'0') + 52,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("not base64: {c}"),
        }
    };
    let mut out = Vec::new();
    for chunk in s.as_bytes().chunks(4) {
        let pad = chunk.iter().filter(|&&c| c == b'=').count();
        let mut n = 0u32;
        for &c in chunk {
            n = (n << 6) | if c == b'=' { 0 } else { val(c) };
        }
        let bytes = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&bytes[..3 - pad]);
    }
    out
}

#[test]
fn the_setup_sheet_shows_every_setup_with_its_picture_tools_and_times() {
    let dir = std::env::temp_dir().join(format!("talas-job-sheet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The job part's project with a vise holding the first setup's stock.
    let text = std::fs::read_to_string(data("job/job-part.talas")).unwrap();
    let vise = "margin_mm = 2.0\n\n[[setups.workholding]]\nkind = \"vise\"\njaw_width_mm = 80.0\n\
                jaw_height_mm = 20.0\njaw_thickness_mm = 15.0\ngrip_mm = 5.0\n";
    assert_eq!(text.matches("margin_mm = 2.0\n").count(), 1);
    let project = dir.join("job-part-vise.talas");
    // The work material: aluminium 6061 with carbide tools (the project's feeds stay typed).
    let text = text.replace(
        "selected_tool = 0\n",
        "selected_tool = 0\nmaterial = { key = \"6061\", tool_material = \"carbide\" }\n",
    );
    std::fs::write(&project, text.replace("margin_mm = 2.0\n", vise)).unwrap();
    let out = dir.join("sheet.html");
    let doc = run_sheet(&project, &out);
    assert_eq!(doc["sheet"].as_str(), Some(out.to_str().unwrap()));
    let html = std::fs::read_to_string(&out).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    for outside in ["<script", "src=\"http", "href=\"http", "url(http"] {
        assert!(!html.contains(outside), "self-contained: {outside}");
    }
    let setups = doc["setups"].as_array().unwrap();
    assert_eq!(setups.len(), 3);
    // The material, in the JSON and on the sheet; each operation says where its speeds are
    // from: the facing's typed 800 mm/min is not the library's, the drilling cycle has none.
    assert_eq!(doc["material"]["name"], "aluminium 6061-T6");
    assert_eq!(doc["material"]["tool_material"], "carbide");
    assert!(html.contains("Material: aluminium 6061-T6 (carbide tools)"));
    let ops: Vec<&serde_json::Value> = setups
        .iter()
        .flat_map(|s| s["operations"].as_array().unwrap())
        .collect();
    for op in &ops {
        let from = &op["speeds_from"];
        let kind = from["kind"].as_str().unwrap();
        assert!(["typed", "typed_only"].contains(&kind), "{op}");
        assert!(
            html.contains(&format!("Speeds {}", from["text"].as_str().unwrap())),
            "{from}"
        );
    }
    let facing = ops.iter().find(|o| o["kind"] == "Facing").unwrap();
    assert_eq!(facing["feed_mm_per_min"], 800.0);
    assert_eq!(facing["speeds_from"]["kind"], "typed");
    let drill = ops.iter().find(|o| o["kind"] == "Hole making").unwrap();
    assert_eq!(drill["speeds_from"]["kind"], "typed_only", "{drill}");
    assert_eq!(html.matches("<section>").count(), 3);
    for (k, s) in setups.iter().enumerate() {
        let name = s["name"].as_str().unwrap();
        assert!(
            html.contains(&format!("<h2>Setup {}: {name}</h2>", k + 1)),
            "setup {name}"
        );
        assert!(html.contains(s["work_offset"].as_str().unwrap()));
        for op in s["operations"].as_array().unwrap() {
            assert!(html.contains(&format!(">{}</td>", op["name"].as_str().unwrap())));
        }
    }
    // Tools: the three of the project, each once, with its number.
    for t in [
        "T1</td><td>Flat 10",
        "T2</td><td>Flat 4",
        "T3</td><td>Drill 6",
    ] {
        assert_eq!(html.matches(t).count(), 1, "{t}");
    }
    // Feeds typed in the project show as typed; every operation has a cycle time.
    assert!(
        html.contains("<td class=\"n\">800</td>"),
        "the facing's 800 mm/min"
    );
    assert!(
        html.contains("<td class=\"n\">8000</td>"),
        "the post's 8000 rpm"
    );
    let rows = html.matches("<tr><td class=\"n\">").count();
    assert!(rows >= 6 + 3, "operation and tool rows: {rows}");
    assert!(
        !html.contains("<td class=\"n\">— ("),
        "an operation without a cycle time"
    );
    // The first setup's stock: a box around the part (60 × 40 × 25) grown by its margin on
    // the sides and the top.
    assert!(
        html.contains("box around the part + "),
        "the first setup's stock kind"
    );
    assert_eq!(
        html.matches("<tr><th>Workholding</th><td>vise</td></tr>")
            .count(),
        1,
        "the vise of the first setup"
    );
    // Pictures: one per setup, 560 × 400 PNG, the part and its stock covering a fair share
    // and some of it darker than the background (shaded faces).
    let pics = pictures(&html);
    assert_eq!(pics.len(), 3);
    // Each says what drew it: the workstation's offscreen renderer in a build with the GUI
    // (when a graphics adapter answers), else the engine's software drawing, saying why.
    assert_eq!(html.matches("<tr><th>Picture</th><td>drawn by ").count(), 3);
    let offscreen = html.matches("drawn by the offscreen renderer (").count();
    let software = html.matches("drawn by software").count();
    assert_eq!(
        offscreen + software,
        3,
        "{offscreen} offscreen, {software} software"
    );
    if cfg!(feature = "gui") && software > 0 {
        assert!(
            html.contains("drawn by software (the offscreen renderer could not draw: "),
            "a GUI build says why the offscreen renderer did not draw"
        );
    }
    for png in &pics {
        let decoder = png::Decoder::new(std::io::Cursor::new(png.as_slice()));
        let mut reader = decoder.read_info().expect("a PNG");
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).expect("a frame");
        assert_eq!((info.width, info.height), (560, 400));
        let px = &buf[..info.buffer_size()];
        let n = px.len() / 3;
        let drawn = px
            .chunks(3)
            .filter(|c| c[0] < 235 || c[1] < 235 || c[2] < 235)
            .count();
        let share = drawn as f64 / n as f64;
        assert!(
            (0.08..0.9).contains(&share),
            "the part covers {share:.2} of the picture"
        );
    }
    // The same job writes the same sheet.
    let again = dir.join("again.html");
    run_sheet(&project, &again);
    assert_eq!(std::fs::read(&again).unwrap(), html.as_bytes());
    let _ = std::fs::remove_dir_all(&dir);
}

use super::*;

/// The (kind, text) pairs of a line's tokens.
fn kinds(line: &str) -> Vec<(TokenKind, &str)> {
    tokenize(line)
        .into_iter()
        .map(|t| (t.kind, &line[t.start..t.end]))
        .collect()
}

#[test]
fn rs274_words_and_semicolon_comment() {
    use TokenKind::*;
    assert_eq!(
        kinds("N10 G01 X1.5 Y-2 F1200 ; cut"),
        vec![
            (LineNumber, "N10"),
            (GCode, "G01"),
            (Axis, "X1.5"),
            (Axis, "Y-2"),
            (FeedSpeedTool, "F1200"),
            (Comment, "; cut"),
        ]
    );
}

#[test]
fn parenthesis_comments_inside_and_unclosed() {
    use TokenKind::*;
    assert_eq!(kinds("(comment)"), vec![(Comment, "(comment)")]);
    assert_eq!(
        kinds("G0 (rapid; in) Z5"),
        vec![(GCode, "G0"), (Comment, "(rapid; in)"), (Axis, "Z5")]
    );
    assert_eq!(kinds("M3 (open"), vec![(MCode, "M3"), (Comment, "(open")]);
}

#[test]
fn packed_words_lowercase_and_decimal_codes() {
    use TokenKind::*;
    assert_eq!(
        kinds("g1x5y.5 G43.4 H1 s10000 t2"),
        vec![
            (GCode, "g1"),
            (Axis, "x5"),
            (Axis, "y.5"),
            (GCode, "G43.4"),
            (Word, "H1"),
            (FeedSpeedTool, "s10000"),
            (FeedSpeedTool, "t2"),
        ]
    );
}

#[test]
fn siemens_keywords_assignments_and_strings() {
    use TokenKind::*;
    assert_eq!(
        kinds("N20 TRAORI"),
        vec![(LineNumber, "N20"), (Keyword, "TRAORI")]
    );
    assert_eq!(
        kinds("CYCLE800(1,\"TC1\") X=10 A=-30.5"),
        vec![
            (Keyword, "CYCLE800"),
            (Comment, "\"TC1\""),
            (Axis, "X=10"),
            (Axis, "A=-30.5"),
        ]
    );
    assert_eq!(
        kinds("MSG(\"no ; comment\")"),
        vec![(Keyword, "MSG"), (Comment, "\"no ; comment\"")]
    );
}

#[test]
fn heidenhain_iso_and_plain_language() {
    use TokenKind::*;
    assert_eq!(
        kinds("N30 M128 X+10 C-90*"),
        vec![
            (LineNumber, "N30"),
            (MCode, "M128"),
            (Axis, "X+10"),
            (Axis, "C-90"),
        ]
    );
    assert_eq!(
        kinds("5 L X+10 Y-5 R0 FMAX"),
        vec![
            (LineNumber, "5"),
            (Word, "L"),
            (Axis, "X+10"),
            (Axis, "Y-5"),
            (Word, "R0"),
            (Keyword, "FMAX"),
        ]
    );
    assert_eq!(
        kinds("7 FUNCTION TCPM F TCP AXIS POS"),
        vec![
            (LineNumber, "7"),
            (Keyword, "FUNCTION"),
            (Keyword, "TCPM"),
            (FeedSpeedTool, "F"),
            (Keyword, "TCP"),
            (Keyword, "AXIS"),
            (Keyword, "POS"),
        ]
    );
}

#[test]
fn tokens_are_ordered_and_inside_the_line() {
    for line in [
        "",
        "%",
        "G1 X-",
        "X+",
        "((nested)",
        "N1 G1 X1 ; é comment",
        "é G1",
        "\"open",
        "  42",
    ] {
        let mut at = 0;
        for t in tokenize(line) {
            assert!(
                t.start >= at && t.end > t.start && t.end <= line.len(),
                "{line:?}"
            );
            assert!(
                line.get(t.start..t.end).is_some(),
                "{line:?}: not on a char boundary"
            );
            at = t.end;
        }
    }
}

#[test]
fn lines_split_once_with_and_without_final_newline() {
    let v = GcodeView::new("G0 X1\r\nG1 Y2\n\nM30\n".into());
    assert_eq!(v.line_count(), 4);
    assert_eq!(v.line(0), Some("G0 X1"));
    assert_eq!(v.line(1), Some("G1 Y2"));
    assert_eq!(v.line(2), Some(""));
    assert_eq!(v.line(3), Some("M30"));
    assert_eq!(v.line(4), None);
    let v = GcodeView::new("M30".into());
    assert_eq!((v.line_count(), v.line(0)), (1, Some("M30")));
    assert_eq!(GcodeView::new(String::new()).line_count(), 1);
}

#[test]
fn search_finds_next_line_and_wraps() {
    let mut v = GcodeView::new("G0 X1\nG1 x2\nM3\nG1 X3\n".into());
    v.set_search_text("X");
    assert_eq!(v.find_next(), Some(0));
    assert_eq!(v.find_next(), Some(1), "case is ignored");
    assert_eq!(v.find_next(), Some(3), "line 2 has no X");
    assert_eq!(v.find_next(), Some(0), "wraps");
    assert_eq!(v.selected_line(), Some(0));
    v.set_search_text("G2");
    assert_eq!(v.find_next(), None);
    assert_eq!(
        v.selected_line(),
        Some(0),
        "a failed search keeps the selection"
    );
}

#[test]
fn size_is_written_in_units() {
    assert_eq!(size_text(812), "812 B");
    assert_eq!(size_text(12_400), "12.4 kB");
    assert_eq!(size_text(3_200_000), "3.2 MB");
}

struct Pane {
    view: GcodeView,
    events: Vec<GcodeEvent>,
}

/// A million-line program in a headless harness: picking a line brings it into view, and
/// clicking the middle of the pane reports that line.
#[test]
fn a_million_lines_scroll_to_a_line_and_click_it() {
    let n = 1_000_000usize;
    let mut text = String::with_capacity(n * 24);
    for i in 0..n {
        text.push_str(&format!("N{i} G1 X{i} Y-{i}.5\n"));
    }
    let mut h = egui_kittest::Harness::builder()
        .with_size(egui::vec2(600.0, 400.0))
        .build_ui_state(
            |ui, p: &mut Pane| {
                if let Some(e) = p.view.ui(ui) {
                    p.events.push(e);
                }
            },
            Pane {
                view: GcodeView::new(text),
                events: Vec::new(),
            },
        );
    h.run_steps(2);
    assert_eq!(h.state().view.line_count(), n);
    // Only the visible rows were tokenized.
    let tokenized = h.state().view.tokens.iter().filter(|t| t.is_some()).count();
    assert!(
        tokenized > 5 && tokenized < 100,
        "{tokenized} lines tokenized"
    );
    let target = 654_321;
    h.state_mut().view.scroll_to_line(target);
    h.run_steps(3);
    let visible = h.state().view.visible.clone();
    assert!(visible.contains(&target), "{visible:?}");
    // The line is centred: click in the middle of the rows.
    let rows = h.state().view.visible.clone();
    let pos = egui::pos2(200.0, 400.0 - (400.0 - 40.0) / 2.0);
    h.hover_at(pos);
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(2);
    let clicked = match h.state().events.last() {
        Some(GcodeEvent::LineClicked(l)) => *l,
        None => panic!("no click event"),
    };
    assert!(rows.contains(&clicked), "{clicked} not in {rows:?}");
    assert!(clicked.abs_diff(target) <= 3, "{clicked} vs {target}");
    assert_eq!(h.state().view.selected_line(), Some(clicked));
    // The arrows step the selection while the pointer is over the pane (and only then).
    h.key_press(egui::Key::ArrowDown);
    h.run_steps(2);
    assert_eq!(h.state().view.selected_line(), Some(clicked));
    h.hover_at(pos);
    h.step();
    h.key_press(egui::Key::ArrowDown);
    h.run_steps(2);
    h.key_press(egui::Key::ArrowDown);
    h.run_steps(2);
    h.key_press(egui::Key::ArrowUp);
    h.run_steps(2);
    assert_eq!(h.state().view.selected_line(), Some(clicked + 1));
    assert_eq!(
        h.state().events.last(),
        Some(&GcodeEvent::LineClicked(clicked + 1))
    );
}

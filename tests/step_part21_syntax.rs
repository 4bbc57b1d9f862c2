//! ISO 10303-21 syntax features, one small exchange structure each. Expected values come from
//! the standard's grammar (ISO 10303-21:2016 §6–7), not from the reader.

use talas::import::step::part21::{MAX_DEPTH, Param, Part21Error, parse};

/// A complete exchange structure around `data` (the DATA section's body); DATA starts on line 8.
fn file(data: &str) -> String {
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('a part'),'2;1');\n\
         FILE_NAME('part.stp','2026-01-01T00:00:00',('me'),('us'),'pre','Talas test','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN {{ 1 0 10303 214 1 1 1 1 }}'));\nENDSEC;\nDATA;\n{data}ENDSEC;\nEND-ISO-10303-21;\n"
    )
}

fn ok(data: &str) -> talas::import::step::part21::Exchange {
    parse(file(data).as_bytes()).unwrap_or_else(|e| panic!("{e}\n{data}"))
}

fn err(data: &str) -> Part21Error {
    parse(file(data).as_bytes()).expect_err(data)
}

/// The parameters of the simple instance #1.
fn params(data: &str) -> Vec<Param> {
    let ex = ok(data);
    ex.get(1)
        .and_then(|i| i.simple())
        .map(|r| r.params.clone())
        .expect("#1")
}

fn one(value: &str) -> Param {
    params(&format!("#1=X({value});\n"))
        .into_iter()
        .next()
        .expect("a parameter")
}

#[test]
fn header_fields() {
    let ex = ok("#1=A();\n");
    assert_eq!(ex.header.description, vec!["a part"]);
    assert_eq!(ex.header.name, "part.stp");
    assert_eq!(ex.header.originating_system, "Talas test");
    assert_eq!(
        ex.header.schema,
        vec!["AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }"]
    );
    assert!(ex.diagnostics.is_empty(), "{:?}", ex.diagnostics);
}

#[test]
fn instance_lines_and_ids() {
    let ex = ok("#10=A();\n\n#7 = B ( ) ;\n");
    assert_eq!(ex.get(10).map(|i| i.line), Some(8));
    assert_eq!(ex.get(7).map(|i| i.line), Some(10));
    assert_eq!(ex.get(7).and_then(|i| i.name()), Some("B"));
    assert!(ex.get(8).is_none());
}

#[test]
fn comments_anywhere_and_records_over_many_lines() {
    let ex = ok(
        "/* lead */#1/*a*/=/*b*/CARTESIAN_POINT/*c*/(/*d*/'p'/*\n multi\n line */,\n(\n1.,\n2.\n,3.)\n)/*e*/;/*f*/\n#2=A(#1);\n",
    );
    let p = ex
        .get(1)
        .and_then(|i| i.record("cartesian_point"))
        .expect("#1");
    assert_eq!(p.param(0).and_then(Param::as_str), Some("p"));
    let coords: Vec<f64> = p
        .param(1)
        .and_then(Param::as_list)
        .expect("list")
        .iter()
        .filter_map(Param::as_f64)
        .collect();
    assert_eq!(coords, [1.0, 2.0, 3.0]);
    // #2 sits on line 8 + 8 = 16 (the record of #1 spans lines 8-15).
    assert_eq!(ex.get(2).map(|i| i.line), Some(16));
}

#[test]
fn any_whitespace_and_crlf_lines() {
    let text = file("#1=A(1,\t2);\n#2=B(\x0c3);\n").replace('\n', "\r\n");
    let ex = parse(text.as_bytes()).expect("CRLF");
    assert_eq!(ex.get(2).map(|i| i.line), Some(9));
    // Old Mac line ends (CR only) count as lines too.
    let text = file("#1=A();\n#2=B();\n").replace('\n', "\r");
    let ex = parse(text.as_bytes()).expect("CR");
    assert_eq!(ex.get(2).map(|i| i.line), Some(9));
}

#[test]
fn keywords_are_case_insensitive() {
    let text = "iso-10303-21;\nheader;\nfile_name('x','',(''),(''),'','','');\nendsec;\ndata;\n#1=cartesian_point('',(0.,0.,0.));\nendsec;\nend-iso-10303-21;\n";
    let ex = parse(text.as_bytes()).expect("lower case");
    assert_eq!(ex.get(1).and_then(|i| i.name()), Some("CARTESIAN_POINT"));
    assert_eq!(ex.header.name, "x");
}

#[test]
fn several_data_sections_share_the_id_space() {
    let text = file("#1=A();\nENDSEC;\nDATA;\n#2=B(#1);\n");
    let ex = parse(text.as_bytes()).expect("two sections");
    assert_eq!(ex.instances.len(), 2);
    // Edition 3 section header with parameters.
    let text = file("#1=A();\nENDSEC;\nDATA('second',('SCHEMA'));\n#2=B(#1);\n");
    assert_eq!(
        parse(text.as_bytes())
            .expect("named section")
            .instances
            .len(),
        2
    );
    // A duplicate across sections is an error naming both lines.
    let e = parse(file("#1=A();\nENDSEC;\nDATA;\n#1=B();\n").as_bytes()).expect_err("dup");
    assert_eq!((e.line, e.id), (11, Some(1)));
    assert!(e.message.contains("line 8"), "{e}");
}

#[test]
fn missing_end_marker_is_a_warning() {
    let text = file("#1=A();\n").replace("END-ISO-10303-21;\n", "");
    let ex = parse(text.as_bytes()).expect("no end marker");
    assert_eq!(ex.diagnostics.len(), 1);
    assert!(ex.diagnostics[0].message.contains("END-ISO-10303-21"));
    // Text after the end marker is ignored with a warning.
    let text = file("#1=A();\n") + "trailing junk \u{1}\n";
    let ex = parse(text.as_bytes()).expect("trailing");
    assert_eq!(ex.diagnostics.len(), 1);
}

#[test]
fn complex_instances() {
    let ex = ok("#1=( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.) );\n#2=(A(1)B(2));\n");
    let unit = ex.get(1).expect("#1");
    assert!(unit.complex);
    assert!(unit.simple().is_none());
    assert_eq!(
        unit.records
            .iter()
            .map(|r| r.name.as_str())
            .collect::<Vec<_>>(),
        ["LENGTH_UNIT", "NAMED_UNIT", "SI_UNIT"]
    );
    assert_eq!(
        unit.record("named_unit").and_then(|r| r.param(0)),
        Some(&Param::Derived)
    );
    let si = unit.record("SI_UNIT").expect("SI_UNIT");
    assert_eq!(si.param(0).and_then(Param::as_enum), Some("MILLI"));
    assert_eq!(si.param(1).and_then(Param::as_enum), Some("METRE"));
    assert_eq!(
        ex.get(2)
            .and_then(|i| i.record("B"))
            .and_then(|r| r.param(0))
            .and_then(Param::as_i64),
        Some(2)
    );
    assert_eq!(ex.instances_of("si_unit").count(), 1);
}

#[test]
fn typed_parameters() {
    let p = one("LENGTH_MEASURE(1.)");
    assert_eq!(
        p,
        Param::Typed("LENGTH_MEASURE".into(), Box::new(Param::Real(1.0)))
    );
    assert_eq!(p.as_f64(), Some(1.0));
    assert_eq!(p.as_typed().map(|t| t.0), Some("LENGTH_MEASURE"));
    let p = one("parameter_value(2)");
    assert_eq!(p.as_i64(), Some(2));
    assert_eq!(
        one("POSITIVE_LENGTH_MEASURE(LENGTH_MEASURE(3.5))").as_f64(),
        Some(3.5)
    );
    assert_eq!(
        one("LABEL('x')"),
        Param::Typed("LABEL".into(), Box::new(Param::String("x".into())))
    );
    // A typed parameter wrapped in dots (seen in generated files) is read with a warning.
    let ex = ok("#1=UNCERTAINTY_MEASURE_WITH_UNIT(.LENGTH_MEASURE(1.0E-7).,#2,'d','');\n#2=A();\n");
    let p = ex
        .get(1)
        .and_then(|i| i.simple())
        .and_then(|r| r.param(0))
        .expect("param");
    assert_eq!(p.as_f64(), Some(1.0e-7));
    assert_eq!(ex.diagnostics.len(), 1);
}

#[test]
fn unset_derived_enums_booleans() {
    let ps = params("#1=X($,*,.T.,.F.,.U.,.UNSPECIFIED.,.c_1.);\n");
    assert!(ps[0].is_unset());
    assert_eq!(ps[1], Param::Derived);
    assert_eq!(ps[2].as_bool(), Some(true));
    assert_eq!(ps[3].as_bool(), Some(false));
    assert_eq!(ps[4].as_bool(), None);
    assert_eq!(ps[5].as_enum(), Some("UNSPECIFIED"));
    assert_eq!(ps[6].as_enum(), Some("C_1"));
    assert_eq!(ps[0].as_f64(), None);
}

#[test]
fn strings_and_escapes() {
    assert_eq!(one("'it''s'").as_str(), Some("it's"));
    assert_eq!(one("''").as_str(), Some(""));
    assert_eq!(one(r"'\X\C4pfel'").as_str(), Some("Äpfel"));
    assert_eq!(one(r"'\X2\03B103B2\X0\'").as_str(), Some("αβ"));
    assert_eq!(one(r"'\X4\0001F527\X0\'").as_str(), Some("\u{1F527}"));
    assert_eq!(one(r"'\S\D'").as_str(), Some("Ä"));
    assert_eq!(one(r"'\PA\\S\D\\'").as_str(), Some("Ä\\"));
    assert_eq!(one("'a;b)c(d,#1'").as_str(), Some("a;b)c(d,#1"));
    assert_eq!(
        one("'Bohrung \u{2300}6'").as_str(),
        Some("Bohrung \u{2300}6")
    );
    // A literal broken over two lines: the line break is not part of the value.
    assert_eq!(one("'long\nvalue'").as_str(), Some("longvalue"));
}

#[test]
fn invalid_utf8_in_strings_is_decoded_lossily_with_a_warning() {
    let mut bytes = file("#1=PRODUCT('caf\u{1}');\n").into_bytes();
    let at = bytes.iter().position(|&b| b == 1).expect("marker");
    bytes[at] = 0xE9; // Latin-1 é, not UTF-8
    let ex = parse(&bytes).expect("lossy");
    let s = ex
        .get(1)
        .and_then(|i| i.simple())
        .and_then(|r| r.param(0))
        .and_then(Param::as_str);
    assert_eq!(s, Some("caf\u{FFFD}"));
    assert_eq!(ex.diagnostics.len(), 1);
    assert_eq!(ex.diagnostics[0].place.as_deref(), Some("line 8, #1"));
}

#[test]
fn very_long_strings_up_to_the_limit() {
    let long = "A".repeat(32_767);
    assert_eq!(
        one(&format!("'{long}'")).as_str().map(str::len),
        Some(32_767)
    );
    let e = err(&format!("#1=X('{long}A');\n"));
    assert_eq!((e.line, e.id), (8, Some(1)));
}

#[test]
fn binary_values() {
    assert_eq!(one("\"0ABC\""), Param::Binary("0ABC".into()));
    assert_eq!(one("\"3\""), Param::Binary("3".into()));
}

#[test]
fn numbers() {
    let ps = params("#1=X(1.,-1.5E-3,1.E+2,0.5,.5,-.25,1e3,+2.,42,-7,+3,0,1.0E-999999);\n");
    let v: Vec<f64> = ps.iter().filter_map(Param::as_f64).collect();
    assert_eq!(
        v,
        [
            1.0, -1.5e-3, 100.0, 0.5, 0.5, -0.25, 1000.0, 2.0, 42.0, -7.0, 3.0, 0.0, 0.0
        ]
    );
    assert!(matches!(ps[0], Param::Real(_)));
    assert_eq!(ps[8], Param::Integer(42));
    assert_eq!(one("9223372036854775807").as_i64(), Some(i64::MAX));
    assert_eq!(one("-9223372036854775808").as_i64(), Some(i64::MIN));
    assert_eq!(one("1.7976931348623157E308").as_f64(), Some(f64::MAX));
    for bad in [
        "1E999999",
        "-1.8E308",
        "9223372036854775808",
        "1.0D0",
        "1_000.0",
        "0x10",
        "1.E",
        "1..2",
    ] {
        let e = err(&format!("#1=X({bad});\n"));
        assert_eq!((e.line, e.id), (8, Some(1)), "{bad}: {e}");
    }
}

#[test]
fn lists_references_and_dangling_refs() {
    let ex = ok("#1=X((),(#2,#3),((1,2),(3)),#9);\n#2=Y(LENGTH_MEASURE(#7));\n#3=Z();\n");
    let r = ex.get(1).and_then(|i| i.simple()).expect("#1");
    assert_eq!(
        r.param(0).and_then(Param::as_list).map(<[Param]>::len),
        Some(0)
    );
    let refs: Vec<u64> = r
        .param(1)
        .and_then(Param::as_list)
        .expect("list")
        .iter()
        .filter_map(Param::as_ref)
        .collect();
    assert_eq!(refs, [2, 3]);
    assert_eq!(
        r.param(2)
            .and_then(Param::as_list)
            .and_then(|l| l[1].as_list())
            .map(<[Param]>::len),
        Some(1)
    );
    assert_eq!(ex.dangling_refs(), vec![(1, 9), (2, 7)]);
}

#[test]
fn user_defined_keywords() {
    let ex = ok("#1=!MY_ENTITY(1);\n#2=(A()!B(2));\n");
    assert_eq!(ex.get(1).and_then(|i| i.name()), Some("MY_ENTITY"));
    assert!(ex.get(2).and_then(|i| i.record("B")).is_some());
}

#[test]
fn byte_order_mark_is_skipped() {
    let mut bytes = vec![0xEF, 0xBB, 0xBF];
    bytes.extend_from_slice(file("#1=A();\n").as_bytes());
    assert_eq!(parse(&bytes).expect("BOM").instances.len(), 1);
}

#[test]
fn nesting_limit() {
    // MAX_DEPTH - 1 nested lists inside the parameter list are fine; one more is refused.
    let nested = |n: usize| format!("#1=X({}1{});\n", "(".repeat(n), ")".repeat(n));
    let ex = ok(&nested(MAX_DEPTH - 1));
    assert_eq!(ex.instances.len(), 1);
    let e = err(&nested(MAX_DEPTH));
    assert_eq!((e.line, e.id), (8, Some(1)));
    assert!(e.message.contains("nested"), "{e}");
    // Far deeper input is refused the same way, without exhausting the stack.
    let e = err(&nested(1_000_000));
    assert_eq!(e.line, 8);
}

#[test]
fn malformed_header_entity_is_skipped_with_a_warning() {
    // Open CASCADE reads such files (Tsh010.stp: unbalanced parenthesis in FILE_DESCRIPTION).
    let text = file("#1=A();\n").replace("(('a part'),'2;1')", "(('a part','2;1')");
    let ex = parse(text.as_bytes()).expect("header skipped");
    assert!(ex.header.description.is_empty());
    assert_eq!(ex.header.name, "part.stp");
    assert_eq!(ex.diagnostics.len(), 1);
    assert_eq!(ex.diagnostics[0].place.as_deref(), Some("line 3"));
}

#[test]
fn error_display_names_line_and_id() {
    let e = err("#1=A();\n#2=B(1,2;\n");
    assert_eq!(
        e.to_string(),
        "line 9, #2: expected ',' or ')' in a parameter list, found ';'"
    );
}

#[test]
fn edition_3_signature_is_skipped_anchor_refused() {
    let text = file("#1=A();\n").replace(
        "END-ISO-10303-21;",
        "ANCHOR;\n<urn:x> = #1;\nENDSEC;\nREFERENCE;\n#5 = <a.stp#7>;\nENDSEC;\nEND-ISO-10303-21;",
    );
    // `<` is not Part 21 text we read: the sections are skipped token by token only as far as
    // the lexer allows, so a file using them is refused at the first `<`.
    let e = parse(text.as_bytes()).expect_err("anchor");
    assert_eq!(e.line, 11);
    let text = file("#1=A();\n").replace(
        "END-ISO-10303-21;",
        "SIGNATURE;\nSIG('abc');\nENDSEC;\nEND-ISO-10303-21;",
    );
    let ex = parse(text.as_bytes()).expect("signature");
    assert_eq!(ex.diagnostics.len(), 1);
}

#[test]
fn warnings_are_capped() {
    let body: String = (1..=1000).map(|i| format!("#{i}=X(.L(1.).);\n")).collect();
    let ex = ok(&body);
    assert_eq!(ex.instances.len(), 1000);
    assert_eq!(
        ex.diagnostics.len(),
        talas::import::step::part21::MAX_WARNINGS + 1
    );
}

#[test]
fn unterminated_directives_are_kept_as_written() {
    // Thousands of `\X2\` without `\X0\` in one literal: kept literally (and decoded in linear
    // time: the reader never rescans the rest of the string for a terminator).
    let raw = r"\X2\00E9".repeat(4000);
    let ex = ok(&format!("#1=X('{raw}');\n"));
    let s = ex
        .get(1)
        .and_then(|i| i.simple())
        .and_then(|r| r.param(0))
        .and_then(Param::as_str);
    assert_eq!(s, Some(raw.as_str()));
    assert_eq!(ex.diagnostics.len(), 1);
}

//! Malformed input never panics, hangs or loses its place: every reader returns a value or an
//! error naming a line inside the input.

mod common;

/// Part 21 (STEP text): the hand-made malformed files are in `tests/data/bad/*.stp` and checked
/// one by one in `tests/step_part21.rs`; here every prefix and thousands of byte-level
/// corruptions of real files are read.
mod part21 {
    use talas::import::step::part21::parse;

    use crate::common::{Lcg, data};

    fn read(rel: &str) -> Vec<u8> {
        let path = data(rel);
        std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// Lines in `bytes` as the reader counts them (`\n`, `\r\n` or a lone `\r` ends a line).
    fn line_count(bytes: &[u8]) -> usize {
        let mut n = 1;
        for (i, &b) in bytes.iter().enumerate() {
            if b == b'\n' || (b == b'\r' && bytes.get(i + 1) != Some(&b'\n')) {
                n += 1;
            }
        }
        n
    }

    /// The Part 21 grammar admits a prefix of a well-formed file only if it stops after the
    /// data section's `ENDSEC;` (then only the end marker is missing, which is a warning) or
    /// after the end marker itself.
    fn complete_enough(prefix: &[u8]) -> bool {
        let text = String::from_utf8_lossy(prefix);
        let t = text.trim_end();
        t.ends_with("ENDSEC;") && t.rfind("DATA;") < t.rfind("ENDSEC;")
            || t.ends_with("END-ISO-10303-21;")
    }

    fn check_prefixes(rel: &str, step: usize) {
        let bytes = read(rel);
        let mut cut = 0;
        while cut <= bytes.len() {
            let prefix = &bytes[..cut];
            match parse(prefix) {
                Ok(ex) => {
                    assert!(
                        complete_enough(prefix),
                        "{rel} cut at {cut}: accepted a truncated file"
                    );
                    assert!(!ex.instances.is_empty());
                }
                Err(e) => {
                    assert!(!complete_enough(prefix), "{rel} cut at {cut}: {e}");
                    assert!(
                        e.line >= 1 && e.line <= line_count(prefix),
                        "{rel} cut at {cut}: {e}"
                    );
                }
            }
            cut += step;
        }
        // The whole file and the file without its final newline parse.
        assert!(parse(&bytes).is_ok());
    }

    #[test]
    fn every_prefix_is_an_error_or_a_complete_file() {
        check_prefixes("rational-trough.stp", 7);
        check_prefixes(
            "real/dodgy-step-files/step-controls/12-3a-shells/Ctl005.stp",
            5,
        );
        check_prefixes("pocket-fillets.stp", 211);
        // The tail of pocket-fillets byte by byte: ENDSEC, the end marker, the final newline.
        let bytes = read("pocket-fillets.stp");
        for cut in bytes.len().saturating_sub(40)..=bytes.len() {
            let prefix = &bytes[..cut];
            assert_eq!(
                parse(prefix).is_ok(),
                complete_enough(prefix),
                "cut at {cut}"
            );
        }
    }

    /// Bytes a corruption draws from: Part 21 punctuation (most likely to confuse a parser),
    /// digits, letters, and anything at all.
    fn corrupt_byte(rng: &mut Lcg) -> u8 {
        const SPECIAL: &[u8] = b"()(),;;='\"#$*./-+E0123456789\\\n\r \x00\xFF";
        if rng.below(3) == 0 {
            rng.bits() as u8
        } else {
            SPECIAL[rng.below(SPECIAL.len())]
        }
    }

    #[test]
    fn corrupted_files_never_panic_and_errors_name_a_line_inside() {
        let mut rng = Lcg(0x5EED_0021);
        let sources = [
            read("bicubic-hills.stp"),
            read("real/dodgy-step-files/step-controls/12-8-mixed/Ctl012.stp"),
        ];
        let mut errors = 0;
        let runs = 1500;
        for run in 0..runs {
            let mut bytes = sources[run % sources.len()].clone();
            for _ in 0..1 + rng.below(4) {
                let at = rng.below(bytes.len());
                match rng.below(3) {
                    0 => bytes[at] = corrupt_byte(&mut rng),
                    1 => bytes.insert(at, corrupt_byte(&mut rng)),
                    _ => {
                        bytes.remove(at);
                    }
                }
            }
            if let Err(e) = parse(&bytes) {
                errors += 1;
                assert!(
                    e.line >= 1 && e.line <= line_count(&bytes),
                    "run {run}: {e}"
                );
            }
        }
        // Most single-byte corruptions of Part 21 punctuation break the syntax; some land in
        // strings or comments and are harmless.
        assert!(
            errors > runs / 4,
            "only {errors} of {runs} corruptions detected"
        );
    }
}

//! Fuzz target: the Part 21 reader must return `Ok` or `Err` for any bytes, never panic, hang
//! or overflow the stack, and every error must name a line inside the input.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match talas::import::step::part21::parse(data) {
        Ok(exchange) => {
            // Accessors must be total on whatever was parsed.
            let _ = exchange.dangling_refs();
            for inst in exchange.instances.values() {
                assert!(inst.line >= 1);
                assert!(!inst.records.is_empty());
            }
        }
        Err(e) => {
            let lines = 1 + data.iter().filter(|&&b| b == b'\n' || b == b'\r').count();
            assert!(
                e.line >= 1 && e.line <= lines,
                "line {} outside 1..={lines}: {e}",
                e.line
            );
        }
    }
});

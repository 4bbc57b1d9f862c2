//! G-code interpreter: any text is an error or a program of finite blocks, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use talas::gcode::{InterpretOptions, interpret};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(program) = interpret(&text, &InterpretOptions::default()) {
        for block in &program.blocks {
            assert!(block.start.is_finite() && block.end.is_finite());
            assert!(block.length_mm().is_finite());
        }
    }
});

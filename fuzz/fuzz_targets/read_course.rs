//! The course-format reader: any text gives a system or an error naming a line inside the file,
//! never a panic; a system read is written back and read again unchanged, and the engine builds
//! or refuses it without a panic.
#![no_main]

use edmd_core::SimBox;
use edmd_fuzz::{check_error, check_loaded};
use edmd_io::{course, Format};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = edmd_io::detect(text);
    match course::parse(text) {
        Ok(s) => {
            let mut out = Vec::new();
            course::write(&mut out, &s.discs, &SimBox::walls(s.lengths)).unwrap();
            let again = course::parse(std::str::from_utf8(&out).unwrap()).expect("reads back");
            assert_eq!(again.discs, s.discs);
            assert_eq!(again.lengths, s.lengths);
            let loaded = edmd_io::parse(text, Format::Course).expect("parse agrees");
            check_loaded(&loaded, text);
        }
        Err(e) => check_error(text, e.line, &e.message),
    }
});

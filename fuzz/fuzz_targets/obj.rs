//! The OBJ reader on arbitrary text (as `read_obj`, which refuses bytes that are not UTF-8).
//! Errors are fine; a panic, an abort or a hang is a finding.
#![no_main]

use std::path::Path;

use foton::scene::io::obj;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = obj::parse_obj(text, Path::new("fuzz.obj"));
    }
});

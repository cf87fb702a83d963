//! The Mitsuba `.serialized` reader on arbitrary bytes: the first mesh (read from the start) and
//! the second (found through the end-of-file dictionary). Errors are fine; a panic, an abort or a
//! hang is a finding.
#![no_main]

use std::path::Path;

use foton::scene::io::serialized;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    for shape_index in [0, 1] {
        let _ = serialized::parse_serialized(data, shape_index, Path::new("fuzz.serialized"));
    }
});

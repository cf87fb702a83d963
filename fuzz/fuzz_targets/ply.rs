//! The PLY reader on arbitrary bytes. Errors are fine; a panic, an abort or a hang is a finding.
#![no_main]

use foton::scene::io::ply;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = ply::parse(&mut &data[..]);
});

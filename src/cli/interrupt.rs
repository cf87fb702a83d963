//! SIGINT and SIGTERM: the first asks the render to stop after the work under way and keep it
//! (the exit code then says which signal: 130 or 143); a second one ends the process at once.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::flag;

/// The exit code of the first signal received (128 + its number), 0 for none.
static EXIT_CODE: OnceLock<Arc<AtomicUsize>> = OnceLock::new();

fn exit_code_flag() -> &'static Arc<AtomicUsize> {
    EXIT_CODE.get_or_init(|| Arc::new(AtomicUsize::new(0)))
}

pub fn install() -> std::io::Result<()> {
    let received = Arc::new(AtomicBool::new(false));
    for signal in [SIGINT, SIGTERM] {
        let code = 128 + signal as u32;
        // Registered first, so it sees the flag as the previous signal left it.
        flag::register_conditional_shutdown(signal, code as i32, Arc::clone(&received))?;
        flag::register(signal, Arc::clone(&received))?;
        flag::register_usize(signal, Arc::clone(exit_code_flag()), code as usize)?;
    }
    Ok(())
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    exit_code_flag().load(Ordering::Relaxed) != 0
}

/// The exit code the process must end with if it was interrupted.
pub fn exit_code() -> Option<u8> {
    u8::try_from(exit_code_flag().load(Ordering::Relaxed))
        .ok()
        .filter(|&c| c != 0)
}

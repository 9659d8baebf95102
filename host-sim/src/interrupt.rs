//! Ctrl-C as a flag: [`flag`] installs (once per process) a SIGINT handler that sets a flag
//! instead of killing the process, so long jobs (animations) can stop cleanly between frames,
//! remove their temporary file and exit with status 130.
//!
//! Only commands that poll the flag install the handler; everywhere else Ctrl-C keeps its
//! default action (and [`crate::output`]'s atomic writes leave no partial file either way).

use std::sync::atomic::AtomicBool;
use std::sync::OnceLock;

/// The exit status of a command stopped by Ctrl-C (128 + SIGINT).
pub const EXIT_INTERRUPTED: u8 = 130;

static FLAG: AtomicBool = AtomicBool::new(false);
static INSTALLED: OnceLock<bool> = OnceLock::new();

/// The process's interrupt flag, set by Ctrl-C from the first call on. If the handler cannot be
/// installed (another one is), the flag is still returned and simply never set by a signal.
pub fn flag() -> &'static AtomicBool {
    INSTALLED.get_or_init(|| {
        ctrlc::set_handler(|| FLAG.store(true, std::sync::atomic::Ordering::SeqCst)).is_ok()
    });
    &FLAG
}

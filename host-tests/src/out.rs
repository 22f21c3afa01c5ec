//! Standard output of the CLI: a closed pipe (`volsample report | head -1`) ends the program
//! quietly with exit status 0 instead of a panic.

use std::io::Write as _;

/// Writes `text` to stdout. On a closed pipe the process exits with status 0 (the reader
/// has what it wanted); on another write error, with status 1 and a message.
pub fn emit(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("volsample: stdout: {e}");
        std::process::exit(1);
    }
}

/// `println!` through [`emit`].
#[macro_export]
macro_rules! say {
    ($($t:tt)*) => {
        $crate::out::emit(&format!("{}\n", format_args!($($t)*)))
    };
}

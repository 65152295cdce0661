//! Writing a command's report to stdout so that a closed pipe (`… | head`)
//! ends the program quietly, as a tool that SIGPIPE stops does, instead of
//! panicking (Rust ignores SIGPIPE, so `println!` panics there).

/// `println!` for what a command reports on stdout; exits 0 once stdout is
/// a closed pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout().lock(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
            eprintln!("error: writing to stdout: {e}");
            std::process::exit(1);
        }
    }};
}

/// A block of lines for stdout, as [`say!`] writes them (nothing for an
/// empty block).
pub fn say_text(text: String) {
    if !text.is_empty() {
        say!("{}", text.trim_end_matches('\n'));
    }
}

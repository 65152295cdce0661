//! The `hypercontact` command line: parses the arguments, runs the command
//! (each in its own file under `cli/`) and prints an error as one line.

use std::process::ExitCode;

use clap::Parser;

mod cli;
mod stages;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    match cli::dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", error_text(&e));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line, each said once.
fn error_text(e: &anyhow::Error) -> String {
    hypercontact_runner::error::said_once(e.chain())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 17: a stage error that quoted its cause and also chained it
    /// printed `X: msg: msg`; each text is said once, distinct causes kept.
    #[test]
    fn each_cause_is_said_once() {
        #[derive(Debug, thiserror::Error)]
        #[error("the load range: {0}")]
        struct Quoting(#[from] Inner);
        #[derive(Debug, thiserror::Error)]
        #[error("p_max is below p_min")]
        struct Inner;
        let e = anyhow::Error::from(Quoting(Inner)).context("stage `gw` failed");
        assert_eq!(
            error_text(&e),
            "stage `gw` failed: the load range: p_max is below p_min"
        );
        let e = anyhow::Error::from(Inner).context("stage `gw`");
        assert_eq!(error_text(&e), "stage `gw`: p_max is below p_min");
    }
}

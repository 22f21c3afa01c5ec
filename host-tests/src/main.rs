//! The `volsample` command-line tool.

use clap::{Parser, Subcommand};

/// Sample and composite RGBA volumes, and show what each sampling choice costs.
#[derive(Parser, Debug)]
#[command(name = "volsample", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// The papers' three-sample ray and an ASCII rendering, Separate vs OpacityWeighted
    /// (the default).
    Demo,
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command.unwrap_or(Command::Demo) {
        Command::Demo => volsample_host::demo::run().map(|s| print!("{s}")),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("volsample: {e}");
            std::process::ExitCode::FAILURE
        }
    }
}

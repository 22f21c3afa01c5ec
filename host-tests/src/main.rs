//! The `volsample` command-line tool.

fn main() {}

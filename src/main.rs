//! `celltissue` command-line interface (filled in by the CLI work item).
fn main() {
    eprintln!("celltissue: CLI not built yet");
    std::process::exit(2);
}

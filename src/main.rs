fn main() -> std::process::ExitCode {
    foton::cli::run()
}

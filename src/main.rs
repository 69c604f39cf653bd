fn main() -> std::process::ExitCode {
    mechfmu::cli::main()
}

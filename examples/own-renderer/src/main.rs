//! `cargo run -p own-renderer [SIZE]`: one frame of the renderer with its six passes, written to
//! `target/examples/own-renderer.png`.

use own_renderer::{Passes, Renderer, World, write_png};
use std::process::ExitCode;

fn main() -> ExitCode {
    // The binary edge installs the logger: wgpu's own warnings reach standard error.
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let size = match std::env::args().nth(1).map(|s| s.parse::<u32>()) {
        None => 256,
        Some(Ok(size)) if (16..=4096).contains(&size) => size,
        Some(_) => {
            eprintln!("error: SIZE must be a whole number of pixels from 16 to 4096");
            return ExitCode::FAILURE;
        }
    };
    let world = World::default();
    let run = || -> Result<(), own_renderer::Error> {
        let mut renderer = Renderer::new(&world, size)?;
        let rgba = renderer.frame(&world, Passes::ALL)?;
        let path = std::path::Path::new("target/examples/own-renderer.png");
        write_png(path, &rgba, size)?;
        println!("wrote {}", path.display());
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

//! The `chiaro` command line.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use bevy_ecs::world::World;
use clap::{Parser, Subcommand};

use chiaro::scene::{Environment, SceneInfo, load_scene};

#[derive(Parser)]
#[command(
    name = "chiaro",
    version,
    about = "A real-time hybrid path tracer for bevy_ecs applications"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print what a scene holds: meshes, triangles, instances, materials and their texture
    /// slots, lights by kind, emissive triangles, camera, environment, bounds, and what import
    /// repaired.
    Info {
        /// A .gltf or .glb file, or builtin:NAME (cornell, furnace, hard-cases, instances,
        /// many-lights), e.g. builtin:instances?n=10000.
        scene: String,
        /// Equirectangular environment image (.hdr or .exr) replacing the scene's environment.
        #[arg(long)]
        env: Option<PathBuf>,
        /// Multiplies the environment image's radiance.
        #[arg(long, default_value_t = 1.0)]
        env_strength: f32,
    },
}

fn main() -> Result<()> {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    match Cli::parse().command {
        Command::Info {
            scene,
            env,
            env_strength,
        } => info(&scene, env, env_strength),
    }
}

fn info(scene: &str, env: Option<PathBuf>, env_strength: f32) -> Result<()> {
    let mut world = World::new();
    let start = Instant::now();
    load_scene(&mut world, scene)?;
    if let Some(path) = env {
        let (environment, repairs) =
            Environment::from_file(&path, env_strength).context("cannot load the environment")?;
        for r in repairs {
            log::warn!("{}: {r}", path.display());
        }
        world.insert_resource(environment);
    }
    let elapsed = start.elapsed();
    let info = SceneInfo::gather(&mut world);
    println!("scene: {scene}");
    print!("{info}");
    println!("load time: {:.1} ms", elapsed.as_secs_f64() * 1e3);
    Ok(())
}

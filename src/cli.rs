//! The command line.

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// freemesh: knowledge-based all-quadrilateral meshing of plane domains.
#[derive(Debug, Parser)]
#[command(name = "freemesh", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Mesh a domain file (JSON, see domain-format.md, or an ASCII DXF
    /// outline with --size).
    Mesh(MeshArgs),
    /// Write the domain file (JSON, format 1.1) of a DXF outline, to edit
    /// it or mesh it later.
    Convert(ConvertArgs),
    /// Print the boundary features of a domain's initial loop: each node's
    /// angle and concavity, each edge's feature and the KB's action.
    Features(FeaturesArgs),
    /// An interactive Prolog toplevel over the knowledge base and the live
    /// front of a domain being meshed (:help inside lists the commands).
    /// With piped input it reads one query or command a line and prints
    /// no prompts, so a session can be scripted.
    Repl(ReplArgs),
    /// Measure a quad mesh, ours or another program's (.msh, ASCII 4.1 or
    /// 2.2 or binary 4.1, or freemesh's .json): angle range, share in [45, 135], scaled
    /// Jacobian, aspect ratio, taper, size jump, and a histogram of angles.
    Quality(QualityArgs),
}

/// Arguments of `freemesh convert`.
#[derive(Debug, clap::Args)]
pub struct ConvertArgs {
    /// The drawing: an ASCII DXF file.
    pub input: PathBuf,
    /// The domain file to write (.json).
    #[arg(short = 'o', long = "output")]
    pub output: PathBuf,
    /// Target boundary segment length (a drawing has none: required).
    #[arg(long, allow_negative_numbers = true)]
    pub size: Option<f64>,
    /// Largest interior element edge.
    #[arg(long, allow_negative_numbers = true)]
    pub max_size: Option<f64>,
}

/// Arguments of `freemesh quality`.
#[derive(Debug, clap::Args)]
pub struct QualityArgs {
    /// The mesh file.
    pub mesh: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `freemesh repl`.
#[derive(Debug, clap::Args)]
pub struct ReplArgs {
    /// A domain file to load at the start (as :load does).
    pub domain: Option<PathBuf>,
    /// Target boundary segment length (replaces the domains' size).
    #[arg(long, allow_negative_numbers = true)]
    pub size: Option<f64>,
    /// A knowledge-base file consulted after the built-in rules. Repeat
    /// for several.
    #[arg(long = "kb")]
    pub kb: Vec<PathBuf>,
}

/// Arguments of `freemesh features`.
#[derive(Debug, clap::Args)]
pub struct FeaturesArgs {
    /// The domain file (JSON, or a DXF outline with --size).
    pub domain: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Target boundary segment length (replaces the domain's size).
    #[arg(long, allow_negative_numbers = true)]
    pub size: Option<f64>,
    /// A knowledge-base file consulted after the built-in rules.
    #[arg(long = "kb")]
    pub kb: Vec<PathBuf>,
}

/// Arguments of `freemesh mesh`.
#[derive(Debug, clap::Args)]
pub struct MeshArgs {
    /// The domain file(s): JSON, or DXF outlines (.dxf, with --size).
    /// Several files, or a quoted glob ('domains/*.json'), are meshed in
    /// parallel, one output per input.
    #[arg(required = true)]
    pub domains: Vec<PathBuf>,
    /// Output file; the format follows the extension (.msh, .vtk, .svg,
    /// .json, .inp for Abaqus and CalculiX). Repeat for several. {stem}
    /// stands for the domain's file name without extension (needed with
    /// several domains: -o 'out/{stem}.msh'). Every output is checked
    /// before meshing: named once, in a folder that exists and can be
    /// written.
    #[arg(short = 'o', long = "output", required = true)]
    pub outputs: Vec<PathBuf>,
    /// Worker threads for several domains, each with its own engine
    /// (default: the number of cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Report where the time went: the engine's queries and time per
    /// element against the host's.
    #[arg(long)]
    pub stats: bool,
    /// Target boundary segment length (replaces the domain's size;
    /// required for a DXF outline).
    #[arg(long, allow_negative_numbers = true)]
    pub size: Option<f64>,
    /// Element order: 1 (4-node quads) or 2 (8-node quads, or 9-node
    /// with --serendipity false), mid-edge nodes on the input's arcs.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub order: u8,
    /// With --order 2: 8-node serendipity quads (true, the default) or
    /// 9-node quads with a centre node (false).
    #[arg(long, action = clap::ArgAction::Set)]
    pub serendipity: Option<bool>,
    /// Largest interior element edge (replaces the domain's max_size); not
    /// below the size. Above it the mesh is graded: fine at the boundary,
    /// coarser inside up to this; equal to it, uniform.
    #[arg(long, allow_negative_numbers = true)]
    pub max_size: Option<f64>,
    /// A knowledge-base file consulted after the built-in rules. Repeat
    /// for several.
    #[arg(long = "kb")]
    pub kb: Vec<PathBuf>,
    /// Write the inference trace as JSON Lines, one object per element
    /// ({stem} as for -o).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Mesh in structured blocks (the paper's Fig. 17): the rules lay the
    /// domain out in large quadrilaterals (bound(block_size, 4) element
    /// sizes), each meshed as a mapping element, so most nodes are
    /// regular; where the blocks' counts cannot agree, meshed free
    /// (uniform: --max-size does not apply)
    #[arg(long)]
    pub blocks: bool,
}

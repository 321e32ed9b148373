//! `edmd render FILE -o OUT --until T --fps F`: frames drawn without a screen.
//!
//! The frames are drawn by `edmd_draw`, the same code the viewer uses, at simulated times
//! `k * time_scale / fps` for `k = 0, 1, ...` up to `--until` (the event loop runs between
//! frames, so motion is exact in every frame). The output kind follows `OUT`: `*.gif` an
//! animated GIF, `*.mp4` an H.264 video made by piping raw frames to `ffmpeg` (which must be
//! installed), and anything else a folder of numbered PNG files.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result};
use clap::Args;
use edmd_core::{Options, OverlapPolicy};
use edmd_draw::{draw_into, rgba, Colouring, Pixmap, Scene};

use crate::args::{parse_positive, parse_time};
use crate::input::{build, load, read_text};
use crate::output::AtomicFile;
use crate::user_error;

/// Disc colouring.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ColourArg {
    /// The file's colours.
    File,
    /// By speed (blue slow, red fast).
    Speed,
    /// By species.
    Species,
}

/// Options of `edmd render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input file (Princeton or course format; `-` for standard input).
    pub file: String,
    /// Output: `NAME.gif`, `NAME.mp4` (needs ffmpeg), or a folder for numbered PNG frames.
    #[arg(long, short, value_name = "OUT")]
    pub output: PathBuf,
    /// Simulated time of the last frame.
    #[arg(long, value_name = "T", value_parser = parse_time, allow_negative_numbers = true)]
    pub until: f64,
    /// Frames per second of the video.
    #[arg(long, value_parser = parse_positive, default_value_t = 25.0)]
    pub fps: f64,
    /// Simulated time per second of video.
    #[arg(long, value_parser = parse_positive, default_value_t = 1.0)]
    pub time_scale: f64,
    /// Frame size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Disc colouring.
    #[arg(long, value_enum, default_value_t = ColourArg::File)]
    pub colour: ColourArg,
    /// Run files with overlapping discs (see `edmd run --allow-overlaps`).
    #[arg(long)]
    pub allow_overlaps: bool,
}

/// `WIDTHxHEIGHT`, each from 16 to 4096.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("size must be WIDTHxHEIGHT with each from 16 to 4096, found '{s}'");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(16..=4096).contains(&w) || !(16..=4096).contains(&h) {
        return Err(bad());
    }
    Ok((w, h))
}

enum Sink {
    Gif(
        gif::Encoder<std::io::BufWriter<std::fs::File>>,
        AtomicFileHolder,
    ),
    Png(PathBuf),
    Ffmpeg(std::process::Child, PathBuf),
}

/// Keeps the GIF's temporary file alive until it is committed.
struct AtomicFileHolder(AtomicFile);

/// Runs `edmd render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let text = read_text(&args.file)?;
    let sys = load(&args.file, &text, None, Default::default())?;
    let overlaps = if args.allow_overlaps {
        OverlapPolicy::Allow
    } else {
        OverlapPolicy::Refuse
    };
    let mut sim = build(
        &args.file,
        &sys,
        Options {
            overlaps,
            ..Default::default()
        },
    )?;
    let (w, h) = args.size;
    let frames = (args.until * args.fps / args.time_scale).floor() as u64 + 1;
    if frames > 100_000 {
        return user_error(format!("render: {frames} frames is too many (at most 100000): lower --fps or --until, or raise --time-scale"));
    }
    let colouring = match args.colour {
        ColourArg::File => Colouring::File,
        ColourArg::Speed => Colouring::Speed,
        ColourArg::Species => Colouring::Species,
    };
    let ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let mut sink = match ext.as_deref() {
        Some("gif") => {
            let holder = AtomicFileHolder(AtomicFile::create(&args.output)?);
            let file =
                std::fs::File::create(holder.0.temp_path()).context("cannot write the GIF")?;
            let mut enc = gif::Encoder::new(std::io::BufWriter::new(file), w as u16, h as u16, &[])
                .context("GIF encoder")?;
            enc.set_repeat(gif::Repeat::Infinite)
                .context("GIF encoder")?;
            Sink::Gif(enc, holder)
        }
        Some("mp4") => Sink::Ffmpeg(
            start_ffmpeg(&args.output, w, h, args.fps)?,
            args.output.clone(),
        ),
        _ => {
            std::fs::create_dir_all(&args.output).map_err(|e| {
                crate::UserError(format!(
                    "{}: cannot create the frame folder: {e}",
                    args.output.display()
                ))
            })?;
            Sink::Png(args.output.clone())
        }
    };
    let progress = (std::io::stderr().is_terminal()).then(|| {
        let pb = indicatif::ProgressBar::new(frames);
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("render {bar:40} {pos}/{len} frames, eta {eta}")
        {
            pb.set_style(style);
        }
        pb
    });
    let mut pixmap = Pixmap::new(w, h).expect("size checked");
    let delay = (100.0 / args.fps).round().max(1.0) as u16;
    for k in 0..frames {
        let t = (k as f64 * args.time_scale / args.fps).min(args.until);
        sim.run_until(t, &mut ());
        draw_into(&Scene::capture(&sim, colouring), &mut pixmap);
        match &mut sink {
            Sink::Gif(enc, _) => {
                let mut px = rgba(&pixmap);
                let mut frame = gif::Frame::from_rgba_speed(w as u16, h as u16, &mut px, 10);
                frame.delay = delay;
                enc.write_frame(&frame).context("writing the GIF")?;
            }
            Sink::Png(dir) => pixmap
                .save_png(dir.join(format!("frame_{k:06}.png")))
                .context("writing a PNG frame")?,
            Sink::Ffmpeg(child, _) => {
                let stdin = child.stdin.as_mut().expect("piped");
                stdin
                    .write_all(&rgba(&pixmap))
                    .context("ffmpeg stopped reading frames")?;
            }
        }
        if let Some(pb) = &progress {
            pb.set_position(k + 1);
        }
    }
    if let Some(pb) = progress {
        pb.finish_and_clear();
    }
    let out = match sink {
        Sink::Gif(enc, holder) => {
            let mut inner = enc.into_inner().context("finishing the GIF")?;
            inner.flush()?;
            drop(inner);
            holder.0.commit_existing()?;
            args.output.clone()
        }
        Sink::Png(dir) => dir,
        Sink::Ffmpeg(mut child, path) => {
            drop(child.stdin.take());
            let status = child.wait()?;
            if !status.success() {
                anyhow::bail!("ffmpeg failed ({status}) writing {}", path.display());
            }
            path
        }
    };
    crate::print_line(&format!(
        "{frames} frames of {w}x{h} written to {} (t = 0 to {})",
        out.display(),
        args.until
    ));
    Ok(())
}

fn start_ffmpeg(out: &Path, w: u32, h: u32, fps: f64) -> Result<std::process::Child> {
    let child = Command::new("ffmpeg")
        .args([
            "-loglevel",
            "error",
            "-y",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgba",
            "-s",
            &format!("{w}x{h}"),
            "-r",
            &fps.to_string(),
            "-i",
            "-",
        ])
        .args([
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
        ])
        .arg(out)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .spawn();
    match child {
        Ok(c) => Ok(c),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => user_error(
            "render: writing MP4 needs the program 'ffmpeg', which is not installed (apt-get install ffmpeg), or write a .gif or a PNG folder instead",
        ),
        Err(e) => Err(e).context("cannot start ffmpeg"),
    }
}

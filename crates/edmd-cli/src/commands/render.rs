//! `edmd render FILE -o OUT --until T --fps F`: frames drawn without a screen.
//!
//! The frames are drawn by `edmd_draw`, the same code the viewer uses, at simulated times
//! `t0 + k * time_scale / fps` for `k = 0, 1, ...` up to `--until` (`t0` is the time a state
//! file carries, `# edmd time`, or 0; `--until` is absolute, as in `edmd run`; the event loop runs between
//! frames, so motion is exact in every frame, and looks at the stop flag every 100 000 events,
//! so a signal is heeded within a frame too). The output kind follows `OUT`: `*.gif` an
//! animated GIF, `*.mp4` an H.264 video made by piping raw frames to `ffmpeg` (which must be
//! installed), and a folder of numbered PNG files when `OUT` ends with `/` or has no extension
//! and is a new or an empty folder. Anything else (`out.png`, a folder with files in it) is
//! refused. Frames are written to a temporary file or folder and moved into place at the end,
//! so an error or a signal leaves nothing behind. For a stepped potential (`# edmd potential`),
//! `--bonds` draws the pairs inside a well or shoulder and `--colour energy` colours each disc
//! by its potential energy; both are refused for hard discs.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use anyhow::{Context, Result};
use clap::Args;
use edmd_core::{Options, OverlapPolicy, Simulation};
use edmd_draw::{draw3_into, draw_into, rgba, Colouring, Pixmap, Scene, Scene3, View};

use crate::args::{parse_positive, parse_time};
use edmd::input::{build, read_any};
use edmd::output::AtomicFile;
use edmd::user_error;

/// Disc colouring.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ColourArg {
    /// The file's colours.
    File,
    /// By speed (viridis: dark purple slow, yellow-green fast).
    Speed,
    /// By species.
    Species,
    /// By potential energy (stepped potentials only): blue bound, grey free, red repelled.
    Energy,
}

/// Options of `edmd render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Input file (Princeton or course format; `-` for standard input).
    pub file: String,
    /// Output: `NAME.gif`, `NAME.mp4` (needs ffmpeg), or a folder for numbered PNG frames (a
    /// path ending with `/`, or without an extension, that is new or an empty folder).
    #[arg(long, short, value_name = "OUT")]
    pub output: PathBuf,
    /// Simulated time of the last frame (absolute: a state file's '# edmd time' is the first).
    #[arg(long, value_name = "T", value_parser = parse_time, allow_negative_numbers = true)]
    pub until: f64,
    /// Frames per second of the video.
    #[arg(long, value_parser = parse_positive, default_value_t = 25.0, allow_negative_numbers = true)]
    pub fps: f64,
    /// Simulated time per second of video.
    #[arg(long, value_parser = parse_positive, default_value_t = 1.0, allow_negative_numbers = true)]
    pub time_scale: f64,
    /// Frame size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "480x480", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Disc colouring.
    #[arg(long, value_enum, default_value_t = ColourArg::File)]
    pub colour: ColourArg,
    /// Stepped potentials: draw a bond between the discs of each pair inside a well or shoulder.
    #[arg(long)]
    pub bonds: bool,
    /// Run files with overlapping discs (see `edmd run --allow-overlaps`).
    #[arg(long)]
    pub allow_overlaps: bool,
    /// 3D files: the viewing direction, `AZIMUTH,ELEVATION` in degrees (azimuth about the z
    /// axis from +x, elevation above the xy plane; z is up) [default: 30,20]
    #[arg(long, value_name = "AZ,EL", value_parser = parse_view, allow_hyphen_values = true)]
    pub view: Option<(f64, f64)>,
    /// 3D files: draw the slice of the box by the plane `x=X`, `y=Y` or `z=Z` instead (the
    /// circles where it cuts the spheres), seen along that axis.
    #[arg(long, value_name = "AXIS=POSITION", value_parser = parse_slice)]
    pub slice: Option<(usize, f64)>,
}

/// `AZIMUTH,ELEVATION` in degrees, the elevation in `[-90, 90]`.
pub fn parse_view(s: &str) -> Result<(f64, f64), String> {
    let bad = || {
        format!("view must be AZIMUTH,ELEVATION in degrees (elevation from -90 to 90), found '{s}'")
    };
    let (a, e) = s.split_once(',').ok_or_else(bad)?;
    let (a, e): (f64, f64) = (
        a.trim().parse().map_err(|_| bad())?,
        e.trim().parse().map_err(|_| bad())?,
    );
    if !a.is_finite() || !(-90.0..=90.0).contains(&e) {
        return Err(bad());
    }
    Ok((a, e))
}

/// `x=X`, `y=Y` or `z=Z`.
pub fn parse_slice(s: &str) -> Result<(usize, f64), String> {
    let bad = || format!("slice must be x=POSITION, y=POSITION or z=POSITION, found '{s}'");
    let (a, p) = s.split_once('=').ok_or_else(bad)?;
    let axis = match a.trim() {
        "x" => 0,
        "y" => 1,
        "z" => 2,
        _ => return Err(bad()),
    };
    let p: f64 = p.trim().parse().map_err(|_| bad())?;
    if !p.is_finite() {
        return Err(bad());
    }
    Ok((axis, p))
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

/// The most frames one render may make.
pub const MAX_FRAMES: f64 = 100_000.0;

enum Sink {
    Gif(gif::Encoder<AtomicFile>),
    Png(FrameDir),
    Ffmpeg(FfmpegChild, AtomicFile),
}

/// ffmpeg, killed if the render fails.
struct FfmpegChild(std::process::Child);

impl Drop for FfmpegChild {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A folder of PNG frames: written into a temporary folder inside it and moved up on
/// [`FrameDir::commit`]; dropped without commit, the temporary folder goes (and the folder too
/// when this render created it).
struct FrameDir {
    out: PathBuf,
    tmp: PathBuf,
    created: bool,
    done: bool,
}

impl FrameDir {
    fn create(out: &Path) -> Result<Self> {
        let fail = |e: std::io::Error| {
            edmd::UserError(format!(
                "{}: cannot create the frame folder: {e}",
                out.display()
            ))
        };
        let created = match std::fs::read_dir(out) {
            Ok(mut entries) => {
                if entries.next().is_some() {
                    return user_error(format!(
                        "{}: the frame folder is not empty (give a new or an empty folder, or a .gif or .mp4 file)",
                        out.display()
                    ));
                }
                false
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                std::fs::create_dir_all(out).map_err(fail)?;
                true
            }
            Err(e) => return Err(fail(e).into()),
        };
        let tmp = out.join(format!(".edmd-{}.tmp", std::process::id()));
        edmd::output::register_temporary(if created { out } else { &tmp });
        let dir = FrameDir {
            out: out.to_path_buf(),
            tmp,
            created,
            done: false,
        };
        std::fs::create_dir(&dir.tmp).map_err(fail)?;
        Ok(dir)
    }

    fn commit(mut self) -> Result<()> {
        for entry in std::fs::read_dir(&self.tmp)? {
            let entry = entry?;
            std::fs::rename(entry.path(), self.out.join(entry.file_name())).map_err(|e| {
                edmd::UserError(format!(
                    "{}: cannot move a frame into place: {e}",
                    self.out.display()
                ))
            })?;
        }
        std::fs::remove_dir(&self.tmp)?;
        self.done = true;
        edmd::output::unregister_temporary(if self.created { &self.out } else { &self.tmp });
        Ok(())
    }
}

impl Drop for FrameDir {
    fn drop(&mut self) {
        if !self.done {
            let _ = std::fs::remove_dir_all(&self.tmp);
            if self.created {
                let _ = std::fs::remove_dir_all(&self.out);
            }
            edmd::output::unregister_temporary(if self.created { &self.out } else { &self.tmp });
        }
    }
}

/// What `-o` asks for.
enum OutKind {
    Gif,
    Mp4,
    Frames,
}

fn out_kind(out: &Path) -> Result<OutKind> {
    let text = out.to_string_lossy();
    let ext = out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let folder = text.ends_with('/') || out.is_dir();
    match ext.as_deref() {
        Some("gif") if !folder => Ok(OutKind::Gif),
        Some("mp4") if !folder => Ok(OutKind::Mp4),
        Some(e) if !folder => user_error(format!(
            "{}: cannot write '.{e}': give NAME.gif, NAME.mp4, or a folder for PNG frames (ending with '/')",
            out.display()
        )),
        _ => Ok(OutKind::Frames),
    }
}

/// Runs `edmd render`.
pub fn run(args: &RenderArgs) -> Result<()> {
    let kind = out_kind(&args.output)?;
    edmd::output::check_distinct(
        &[("the input file", Path::new(&args.file))],
        &[("--output", &args.output)],
    )?;
    let colouring = match args.colour {
        ColourArg::File => Colouring::File,
        ColourArg::Speed => Colouring::Speed,
        ColourArg::Species => Colouring::Species,
        ColourArg::Energy => Colouring::Energy,
    };
    let bonds = args.bonds;
    match read_any(&args.file, None, Default::default(), None)? {
        edmd_io::AnyLoaded::Two(sys) => {
            if args.slice.is_some() || args.view.is_some() {
                let what = if args.slice.is_some() {
                    "--slice"
                } else {
                    "--view"
                };
                return user_error(format!(
                    "render: {what} applies to 3D files, and this one is 2D"
                ));
            }
            render_in(args, sys, kind, |sim, pm| {
                let scene = Scene::capture(sim, colouring);
                draw_into(&if bonds { scene.with_bonds(sim) } else { scene }, pm)
            })
        }
        edmd_io::AnyLoaded::One(sys) => {
            if args.slice.is_some() || args.view.is_some() {
                let what = if args.slice.is_some() {
                    "--slice"
                } else {
                    "--view"
                };
                return user_error(format!(
                    "render: {what} applies to 3D files, and this one is 1D (rods on a line)"
                ));
            }
            if bonds {
                return user_error(
                    "render: --bonds draws the pairs of a stepped potential, which rods on a line (1D) do not take",
                );
            }
            render_in(args, sys, kind, |sim, pm| {
                edmd_draw::draw_line_into(&edmd_draw::SceneLine::capture(sim, colouring), pm)
            })
        }
        edmd_io::AnyLoaded::Three(sys) => {
            if args.slice.is_some() && args.view.is_some() {
                return user_error(
                    "render: --view and --slice are two ways to draw a 3D file: give one",
                );
            }
            let (azimuth, elevation) = args.view.unwrap_or((30.0, 20.0));
            let view = match args.slice {
                Some((axis, position)) => {
                    let l = sys.sim_box.lengths[axis];
                    if !(0.0..=l).contains(&position) {
                        return user_error(format!(
                            "render: --slice {}={position} is outside the box (0 to {l})",
                            ["x", "y", "z"][axis]
                        ));
                    }
                    View::Slice { axis, position }
                }
                None => View::Orbit { azimuth, elevation },
            };
            render_in(args, sys, kind, |sim, pm| {
                let scene = Scene3::capture(sim, colouring);
                let scene = if bonds { scene.with_bonds(sim) } else { scene };
                draw3_into(&scene, view, pm)
            })
        }
    }
}

/// Renders a system of dimension `D`, each frame drawn by `picture`.
fn render_in<const D: usize>(
    args: &RenderArgs,
    sys: edmd_io::LoadedSystem<D>,
    kind: OutKind,
    picture: impl Fn(&Simulation<D>, &mut Pixmap),
) -> Result<()> {
    // A state file carries its time ('# edmd time'): the film starts there and --until is
    // absolute, as in `edmd run`.
    let t0 = sys.time;
    if args.until < t0 {
        return user_error(format!(
            "{}: the state is at t = {t0} ('# edmd time'), after --until {}: give a later end time",
            args.file, args.until
        ));
    }
    let span = args.until - t0;
    // Divided first, so that a huge span over a huge time scale is not an overflow.
    let frames = (span / args.time_scale * args.fps).floor() + 1.0;
    if frames.is_nan() || frames > MAX_FRAMES {
        let count = if frames.is_finite() {
            format!("{frames:.3e}")
        } else {
            "over 1e308".to_string()
        };
        return user_error(format!("render: {count} frames is too many (at most {MAX_FRAMES:.0}): lower --fps or --until, or raise --time-scale"));
    }
    let frames = frames as u64;
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
    if !sim.is_stepped() {
        let asked = if args.bonds {
            Some("--bonds")
        } else if args.colour == ColourArg::Energy {
            Some("--colour energy")
        } else {
            None
        };
        if let Some(option) = asked {
            return user_error(format!(
                "{}: {option} needs a stepped potential (a well or shoulder, '# edmd potential'), and this file has hard discs only",
                args.file
            ));
        }
    }
    if t0 != 0.0 {
        sim.start_at(t0)
            .or_else(|e| user_error(format!("{}: {e}", args.file)))?;
    }
    edmd::check_until(&sim, &args.file, args.until)?;
    let (w, h) = args.size;
    crate::commands::experiment::common::install_ctrlc();
    let mut sink = match kind {
        OutKind::Gif => {
            let file = AtomicFile::create(&args.output)?;
            let mut enc =
                gif::Encoder::new(file, w as u16, h as u16, &[]).context("GIF encoder")?;
            enc.set_repeat(gif::Repeat::Infinite)
                .context("GIF encoder")?;
            Sink::Gif(enc)
        }
        OutKind::Mp4 => {
            let file = AtomicFile::create(&args.output)?;
            let path = file.temp_path().unwrap_or(file.target()).to_path_buf();
            Sink::Ffmpeg(FfmpegChild(start_ffmpeg(&path, w, h, args.fps)?), file)
        }
        OutKind::Frames => Sink::Png(FrameDir::create(&args.output)?),
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
        if crate::commands::experiment::common::stop_requested() {
            return edmd::interrupted(format!(
                "interrupted at frame {k} of {frames}: nothing written"
            ));
        }
        let t = t0 + (k as f64 * args.time_scale / args.fps).min(span);
        // Frames far apart in simulated time can take minutes each: the stop flag is also
        // looked at while running to the frame.
        if !edmd::run_until_or_stop(&mut sim, t, &mut ())? {
            return edmd::interrupted(format!(
                "interrupted before frame {k} of {frames}: nothing written"
            ));
        }
        picture(&sim, &mut pixmap);
        match &mut sink {
            Sink::Gif(enc) => {
                let mut px = rgba(&pixmap);
                let mut frame = gif::Frame::from_rgba_speed(w as u16, h as u16, &mut px, 10);
                frame.delay = delay;
                enc.write_frame(&frame).context("writing the GIF")?;
            }
            Sink::Png(dir) => pixmap
                .save_png(dir.tmp.join(format!("frame_{k:06}.png")))
                .map_err(|e| {
                    edmd::UserError(format!(
                        "{}: cannot write a PNG frame: {e}",
                        dir.out.display()
                    ))
                })?,
            Sink::Ffmpeg(child, _) => {
                let stdin = child.0.stdin.as_mut().expect("piped");
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
        Sink::Gif(enc) => {
            let file = enc.into_inner().context("finishing the GIF")?;
            file.commit()?;
            args.output.clone()
        }
        Sink::Png(dir) => {
            let out = dir.out.clone();
            dir.commit()?;
            out
        }
        Sink::Ffmpeg(mut child, file) => {
            drop(child.0.stdin.take());
            let status = child.0.wait()?;
            if !status.success() {
                anyhow::bail!("ffmpeg failed ({status}) writing {}", args.output.display());
            }
            file.commit_existing()?;
            args.output.clone()
        }
    };
    let s = if frames == 1 { "" } else { "s" };
    edmd::front::print_line(&format!(
        "{frames} frame{s} of {w}x{h} written to {} (t = {t0} to {})",
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
            "-f",
            "mp4",
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

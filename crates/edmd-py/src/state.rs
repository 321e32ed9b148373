//! A simulation in one dimension with what the Python object keeps beside it: the format it
//! was read in, the attached measurements, and the chunked run that lets Python look for Ctrl-C.

use std::time::Instant;

pub use edmd::checkpoint::Measuring;
use edmd::measure::{Measure, Table};
use edmd_core::{Observer, Simulation};
use edmd_io::Format;

/// Wall-clock time one chunk of a run aims at: Ctrl-C is noticed within about this long.
const CHUNK_SECONDS: f64 = 0.05;

/// Events processed one at a time at the start of a run, to learn how much simulated time a
/// chunk should span.
const PROBE_EVENTS: u32 = 1000;

/// Events per chunk of `run(events=N)`.
pub const EVENT_CHUNK: u64 = 1 << 18;

/// A simulation of dimension `D` and what the Python object keeps with it.
pub struct State<const D: usize> {
    pub sim: Simulation<D>,
    /// The format `write` uses when neither a format nor a known extension is given.
    pub format: Format,
    pub measuring: Option<Measuring<D>>,
    /// The thread whose `run` is under way, if one is. Between the chunks of a run (and in
    /// its callbacks) the Python object is not borrowed, so this is what tells another thread,
    /// or a callback calling `run`, that the simulation is busy.
    pub running: Option<std::thread::ThreadId>,
}

impl<const D: usize> State<D> {
    pub fn new(sim: Simulation<D>, format: Format) -> Self {
        State {
            sim,
            format,
            measuring: None,
            running: None,
        }
    }

    /// The state's checkpoint bytes, measurements included: `edmd run` continues them, and
    /// pickles are made of them.
    pub fn checkpoint(&self) -> Result<Vec<u8>, String> {
        edmd::checkpoint::checkpoint_bytes(&self.sim, self.format, self.measuring.as_ref())
            .map_err(|e| format!("checkpoint: {e:#}"))
    }

    /// A state from checkpoint bytes (measurements included).
    pub fn from_checkpoint(bytes: &[u8]) -> Result<Self, String> {
        let (sim, format, measuring) = edmd::checkpoint::from_checkpoint_bytes::<D>(bytes)?;
        Ok(State {
            sim,
            format,
            measuring,
            running: None,
        })
    }

    /// The stall the engine stopped at, as a message (the run's clock stopped advancing).
    pub fn stalled(&self) -> Option<String> {
        self.sim.stalled().map(|s| s.to_string())
    }

    /// Attaches `which`, sampled every `every` from now.
    pub fn measure(&mut self, which: &[Measure], every: f64) {
        self.measuring = Some(Measuring::new(&self.sim, which, every));
    }

    /// The summaries and tables of the attached measurements.
    pub fn results(&self) -> Option<(serde_json::Value, Vec<Table>)> {
        self.measuring.as_ref().map(|m| m.obs.results(&self.sim))
    }

    /// Takes a sample if one is due at the current time.
    pub fn sample_if_due(&mut self) {
        if let Some(m) = &mut self.measuring {
            if m.next_sample() <= self.sim.time() {
                m.obs.sample(&self.sim);
                // After `run(events=...)` several sample times may have passed: one sample
                // stands for them all, and the next is the first one still ahead.
                let passed = ((self.sim.time() - m.start) / m.every).floor();
                m.samples = (m.samples + 1).max(passed as u64);
            }
        }
    }

    /// `run_until(t)` with the attached measurements watching.
    fn run_until(&mut self, t: f64) {
        match &mut self.measuring {
            Some(m) => self.sim.run_until(t, &mut m.obs),
            None => self.sim.run_until(t, &mut ()),
        }
    }

    /// One chunk of a run to `t_end`: about [`CHUNK_SECONDS`] of work. `span` is the simulated
    /// time the next chunk covers (0 at first: the chunk then learns it from a few events) and
    /// is adjusted from the wall-clock time this one took. Returns true once the simulation is
    /// at `t_end`. Where a run stops does not change its trajectory (positions are computed on
    /// demand), so the chunks give the same result as one `run_until(t_end)`.
    pub fn chunk_until(&mut self, t_end: f64, span: &mut f64) -> bool {
        let t0 = self.sim.time();
        if t0 >= t_end {
            self.run_until(t_end);
            return true;
        }
        let started = Instant::now();
        if *span <= 0.0 {
            for _ in 0..PROBE_EVENTS {
                match self.sim.step(t_end) {
                    Some(e) => {
                        if let Some(m) = &mut self.measuring {
                            m.obs.on_event(&e, &self.sim);
                        }
                    }
                    None => {
                        self.run_until(t_end);
                        return true;
                    }
                }
            }
            let covered = self.sim.time() - t0;
            let seconds = started.elapsed().as_secs_f64().max(1e-6);
            *span = if covered > 0.0 {
                covered * (CHUNK_SECONDS / seconds).min(100.0)
            } else {
                (t_end - t0) * 1e-6
            };
            return false;
        }
        let t1 = (t0 + *span).min(t_end);
        self.run_until(t1);
        let seconds = started.elapsed().as_secs_f64();
        *span *= if seconds > 0.0 {
            (CHUNK_SECONDS / seconds).clamp(0.25, 4.0)
        } else {
            4.0
        };
        t1 >= t_end
    }

    /// Up to `n` events with the measurements watching; returns how many were processed.
    pub fn run_events(&mut self, n: u64) -> u64 {
        match &mut self.measuring {
            Some(m) => self.sim.run_events(n, &mut m.obs),
            None => self.sim.run_events(n, &mut ()),
        }
    }
}

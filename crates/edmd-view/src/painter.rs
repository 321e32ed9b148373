//! Drawing on a second thread: while the worker draws one frame with `edmd_draw::draw_any_into`,
//! the window thread runs the simulation to the next frame and paints the interface.

use std::sync::mpsc::{channel, Receiver, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use edmd_draw::{draw_any_into, AnyScene, Pixmap};

/// A drawn frame: the scene and its picture.
pub struct Picture {
    /// What was drawn (kept to find the disc under the pointer).
    pub scene: AnyScene,
    /// The picture.
    pub pixmap: Pixmap,
    /// Time the worker spent drawing it.
    pub took: Duration,
}

/// A drawing thread with one job at a time.
pub struct Painter {
    jobs: Option<Sender<(AnyScene, Pixmap)>>,
    done: Receiver<Picture>,
    worker: Option<JoinHandle<()>>,
    busy: bool,
    spare: Vec<Pixmap>,
}

impl Painter {
    /// Starts the worker; `wake` is called after each finished picture (to request a repaint).
    pub fn new(wake: impl Fn() + Send + 'static) -> Self {
        let (jobs, inbox) = channel::<(AnyScene, Pixmap)>();
        let (outbox, done) = channel();
        let worker = std::thread::Builder::new()
            .name("edmd-view draw".into())
            .spawn(move || {
                for (scene, mut pixmap) in inbox {
                    let t0 = Instant::now();
                    draw_any_into(&scene, &mut pixmap);
                    let took = t0.elapsed();
                    if outbox
                        .send(Picture {
                            scene,
                            pixmap,
                            took,
                        })
                        .is_err()
                    {
                        break;
                    }
                    wake();
                }
            })
            .expect("start the drawing thread");
        Painter {
            jobs: Some(jobs),
            done,
            worker: Some(worker),
            busy: false,
            spare: Vec::new(),
        }
    }

    /// Whether a picture is being drawn.
    pub fn busy(&self) -> bool {
        self.busy
    }

    /// Starts drawing `scene` at `width` x `height` pixels (the caller checks [`Self::busy`]).
    pub fn submit(&mut self, scene: AnyScene, width: u32, height: u32) {
        let pixmap = match self.spare.pop() {
            Some(p) if (p.width(), p.height()) == (width, height) => p,
            _ => Pixmap::new(width.max(1), height.max(1)).expect("non-zero size"),
        };
        if let Some(jobs) = &self.jobs {
            self.busy = jobs.send((scene, pixmap)).is_ok();
        }
    }

    /// The finished picture, if there is one.
    pub fn finished(&mut self) -> Option<Picture> {
        let p = self.done.try_recv().ok()?;
        self.busy = false;
        Some(p)
    }

    /// Waits for the picture being drawn (if any) and returns it.
    pub fn wait(&mut self) -> Option<Picture> {
        if !self.busy {
            return None;
        }
        let p = self.done.recv().ok()?;
        self.busy = false;
        Some(p)
    }

    /// Gives back a pixmap for reuse.
    pub fn recycle(&mut self, pixmap: Pixmap) {
        self.spare.clear();
        self.spare.push(pixmap);
    }
}

impl Drop for Painter {
    fn drop(&mut self) {
        self.jobs = None;
        if let Some(w) = self.worker.take() {
            let _ = w.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Arc;

    #[test]
    fn draws_what_it_is_given_like_draw() {
        let woken = Arc::new(AtomicUsize::new(0));
        let w = woken.clone();
        let mut p = Painter::new(move || {
            w.fetch_add(1, Ordering::SeqCst);
        });
        let scene = edmd_draw::Scene {
            lengths: [1.0, 1.0],
            positions: vec![edmd_core::Vector::new([0.5, 0.5])],
            radii: vec![0.2],
            colours: vec![[200, 0, 0]],
            ..edmd_draw::Scene::default()
        };
        assert!(!p.busy());
        p.submit(edmd_draw::AnyScene::Flat(scene.clone()), 120, 100);
        assert!(p.busy());
        let pic = p.wait().unwrap();
        assert!(!p.busy());
        assert_eq!(pic.pixmap.data(), edmd_draw::draw(&scene, 120, 100).data());
        p.recycle(pic.pixmap);
        assert!(p.finished().is_none());
        drop(p); // joins the worker, which wakes the window after each picture
        assert_eq!(woken.load(Ordering::SeqCst), 1);
    }
}

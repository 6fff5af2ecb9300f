//! The reference off the UI thread: the harness's ray tracer on a worker thread, at a reduced
//! resolution refined in [`LEVELS`] passes, cached per scene, light and camera.

use glam::Vec3;
use soft_shadow_core::{Camera, CpuContext, Light, SceneGeometry};
use soft_shadow_reference::ground_truth::{GroundTruthSettings, RayTracer};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};

/// The refinement passes: image size divisor, strata per side, replicates.
pub const LEVELS: [(u32, u32, u32); 3] = [(8, 4, 2), (4, 8, 2), (2, 16, 2)];

/// Entries the cache keeps before it starts over.
const CACHE_ENTRIES: usize = 64;

/// One pass of the reference: `V` per pixel of a `width` x `height` image, negative where no
/// receiver covers the pixel or no light point reaches it.
#[derive(Clone, Debug)]
pub struct ReferenceImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Which of [`LEVELS`] this is.
    pub level: usize,
    /// Row-major `V`.
    pub data: Vec<f32>,
    /// The number of the request it answers (distinct per key and request).
    pub serial: u64,
}

/// What one reference is of: scene, light, camera, view size.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceKey {
    /// The scene's id (the viewer numbers the scenes it opens).
    pub scene: u64,
    /// The light.
    pub light: Light,
    /// The camera.
    pub camera: Camera,
    /// View width in pixels.
    pub width: u32,
    /// View height in pixels.
    pub height: u32,
}

impl ReferenceKey {
    fn id(&self) -> String {
        format!("{self:?}")
    }
}

enum Message {
    Scene(u64, Arc<SceneGeometry>),
    Job(u64, ReferenceKey),
}

/// The worker and its cache.
pub struct References {
    jobs: Sender<Message>,
    results: Receiver<(String, ReferenceImage)>,
    cache: HashMap<String, ReferenceImage>,
    in_flight: Option<String>,
    latest: Arc<AtomicU64>,
    current: Option<String>,
}

impl Default for References {
    fn default() -> Self {
        Self::new()
    }
}

impl References {
    /// Starts the worker thread (it ends when this is dropped).
    pub fn new() -> Self {
        let (jobs, inbox) = channel::<Message>();
        let (outbox, results) = channel();
        let latest = Arc::new(AtomicU64::new(0));
        let seen = latest.clone();
        std::thread::Builder::new()
            .name("reference".into())
            .spawn(move || worker(inbox, outbox, seen))
            .expect("spawn the reference thread");
        Self {
            jobs,
            results,
            cache: HashMap::new(),
            in_flight: None,
            latest,
            current: None,
        }
    }

    /// The scene the next requests are of (its casters are traced).
    pub fn set_scene(&mut self, id: u64, geometry: Arc<SceneGeometry>) {
        let _ = self.jobs.send(Message::Scene(id, geometry));
    }

    /// Makes `key` the current reference; the worker refines it unless the cache has it whole
    /// or it is the job in flight (a newer request cancels an older one). Never waits.
    pub fn request(&mut self, key: ReferenceKey) {
        let id = key.id();
        self.current = Some(id.clone());
        let done = self
            .cache
            .get(&id)
            .is_some_and(|r| r.level + 1 == LEVELS.len());
        if done || self.in_flight.as_ref() == Some(&id) {
            return;
        }
        let n = self.latest.fetch_add(1, Ordering::Relaxed) + 1;
        self.in_flight = Some(id);
        let _ = self.jobs.send(Message::Job(n, key));
    }

    /// Takes the worker's finished passes into the cache; true when the current one improved.
    pub fn poll(&mut self) -> bool {
        let mut improved = false;
        while let Ok((id, image)) = self.results.try_recv() {
            if self.cache.len() >= CACHE_ENTRIES && !self.cache.contains_key(&id) {
                self.cache.clear();
            }
            if image.level + 1 == LEVELS.len() && self.in_flight.as_ref() == Some(&id) {
                self.in_flight = None;
            }
            improved |= self.current.as_ref() == Some(&id);
            self.cache.insert(id, image);
        }
        improved
    }

    /// The best pass of the current reference so far.
    pub fn current(&self) -> Option<&ReferenceImage> {
        self.current.as_ref().and_then(|id| self.cache.get(id))
    }

    /// Which pass of which reference [`References::current`] is: the request's number and the
    /// level (`None` before the first pass).
    pub fn current_pass(&self) -> Option<(u64, usize)> {
        let id = self.current.as_ref()?;
        self.cache.get(id).map(|r| (r.serial, r.level))
    }

    /// One line for the panel: how far the current reference is refined.
    pub fn status(&self) -> String {
        match self.current() {
            None => "reference: computing (off the UI thread)".into(),
            Some(r) if r.level + 1 == LEVELS.len() => {
                format!("reference: current, {}x{}", r.width, r.height)
            }
            Some(r) => format!(
                "reference: current at {}x{}, refining (pass {} of {})",
                r.width,
                r.height,
                r.level + 2,
                LEVELS.len()
            ),
        }
    }
}

fn worker(
    inbox: Receiver<Message>,
    outbox: Sender<(String, ReferenceImage)>,
    latest: Arc<AtomicU64>,
) {
    let cpu = CpuContext::new();
    let mut scene: Option<(u64, Arc<SceneGeometry>, RayTracer)> = None;
    while let Ok(first) = inbox.recv() {
        // Everything queued: every scene change applies, only the newest job runs.
        let mut job = None;
        for m in std::iter::once(first).chain(inbox.try_iter()) {
            match m {
                Message::Scene(id, g) => {
                    let tracer = RayTracer::new(&g.casters);
                    scene = Some((id, g, tracer));
                }
                Message::Job(n, key) => job = Some((n, key)),
            }
        }
        let (Some((n, key)), Some((id, geometry, tracer))) = (job, scene.as_ref()) else {
            continue;
        };
        if key.scene != *id {
            continue;
        }
        for (level, &(div, strata_side, replicates)) in LEVELS.iter().enumerate() {
            if latest.load(Ordering::Relaxed) != n {
                break;
            }
            let (w, h) = ((key.width / div).max(1), (key.height / div).max(1));
            let view = key.camera.view(w, h);
            let g = soft_shadow_core::raster::gbuffer(
                cpu.pool(),
                &view,
                key.camera.eye,
                w,
                h,
                &geometry.receivers,
            );
            let covered: Vec<usize> = (0..g.data().len())
                .filter(|&i| g.data()[i].covered)
                .collect();
            let ps: Vec<Vec3> = covered.iter().map(|&i| g.data()[i].position).collect();
            let ns: Vec<Vec3> = covered.iter().map(|&i| g.data()[i].normal).collect();
            let settings = GroundTruthSettings {
                strata_side,
                replicates,
                ..Default::default()
            };
            let refs = tracer.references(&key.light, &ps, &ns, &settings);
            let mut data = vec![-1.0; (w * h) as usize];
            for (&i, r) in covered.iter().zip(refs) {
                if let Some(r) = r {
                    data[i] = r.visibility;
                }
            }
            let image = ReferenceImage {
                width: w,
                height: h,
                level,
                data,
                serial: n,
            };
            if outbox.send((key.id(), image)).is_err() {
                return;
            }
        }
    }
}

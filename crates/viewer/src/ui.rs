//! The panel and the 3D view's input, egui 0.37: what the user edits ([`Model`]) and the
//! widgets that edit it. Nothing here touches the GPU.

use crate::lamps::{LampLine, LampsView};
use crate::renderer::{PassTimes, ViewMode};
use crate::scene::SceneSource;
use crate::state::{SIZE_RANGE, ViewState};
use soft_shadow_core::{Backend, DeviceLimits, LightKind, Registry};
use soft_shadow_reference::scenes::catalogue::SCENE_NAMES;
use soft_shadow_reference::scenes::lamps::LAMP_SCENES;
use std::collections::VecDeque;
use std::path::PathBuf;

/// Width of the side panel, logical pixels.
pub const PANEL_WIDTH: f32 = 300.0;

/// Frame statistics for the panel and the command-line summary.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    /// Wall time between frames, milliseconds, newest last.
    pub frame_ms: VecDeque<f32>,
    /// CPU time recording each pass, last frame.
    pub passes: PassTimes,
    /// GPU time of each pass (G-buffer, technique, compared technique, shading), milliseconds,
    /// from the latest timestamps read back.
    pub gpu_ms: Option<[f64; 4]>,
    /// Every frame's CPU pass times and GPU times, for the command-line summary.
    pub log: Vec<(PassTimes, Option<[f64; 4]>)>,
}

/// Map sides the panel offers.
const RESOLUTIONS: [u32; 8] = [128, 256, 512, 1024, 2048, 4096, 8192, 16384];

/// What the panel asked for this frame.
#[derive(Default)]
pub(crate) struct Actions {
    /// A scene to open.
    pub(crate) open: Option<SceneSource>,
    /// Write a screenshot.
    pub(crate) screenshot: bool,
}

/// The state the panel edits (everything but the GPU objects).
pub(crate) struct Model {
    pub(crate) registry: Registry,
    pub(crate) state: ViewState,
    pub(crate) messages: VecDeque<String>,
    pub(crate) file_field: String,
    pub(crate) scene_name: String,
    /// Size the 3D view should have, physical pixels.
    pub(crate) view_px: (u32, u32),
    /// Where the 3D view starts in the window, physical pixels.
    pub(crate) view_origin_px: (u32, u32),
    pub(crate) stats: Stats,
    pub(crate) actions: Actions,
    pub(crate) reference_status: String,
    pub(crate) lost: Option<String>,
    pub(crate) timestamps: bool,
    /// The device's limits on a map's side.
    pub(crate) device: DeviceLimits,
    /// A scene of lamps' budget and picks (`None`: a scene of one light).
    pub(crate) lamps: Option<LampsPanel>,
}

/// What the panel shows of a scene of lamps: the budget it edits, the last frame's picks.
pub(crate) struct LampsPanel {
    /// The frame budget, milliseconds.
    pub(crate) budget_ms: f64,
    /// Every lamp's pick, last frame.
    pub(crate) lines: Vec<LampLine>,
    /// Maps made and kept last frame.
    pub(crate) maps: (usize, usize),
    /// The last frame's predicted time, milliseconds (the picks' predictions summed).
    pub(crate) predicted_ms: f64,
}

impl LampsPanel {
    pub(crate) fn new(budget_ms: f64) -> Self {
        Self {
            budget_ms,
            lines: Vec::new(),
            maps: (0, 0),
            predicted_ms: 0.0,
        }
    }

    /// Takes the last frame's picks and counts from `view`.
    pub(crate) fn update(&mut self, view: &LampsView) {
        self.lines = view.lines();
        self.predicted_ms = self.lines.iter().filter_map(|l| l.predicted_ms).sum();
        self.maps = view
            .stats
            .as_ref()
            .map_or((0, 0), |s| (s.maps_generated, s.maps_reused));
    }

    /// The command-line summary: frame rate, the budget and every lamp's pick (the passes'
    /// times follow it, the frame pipeline and the lamps' `V` as the technique).
    pub(crate) fn summary(&self, stats: &Stats) -> String {
        use std::fmt::Write as _;
        let mut frames: Vec<f32> = stats.frame_ms.iter().skip(2).copied().collect();
        frames.sort_by(f32::total_cmp);
        let ms = frames.get(frames.len() / 2).copied().unwrap_or(f32::NAN);
        let mut s = format!(
            "{} lamps under a {} ms budget: frame {ms:.1} ms median ({:.1} fps); last frame \
             {:.2} ms predicted, {} maps made, {} kept\n",
            self.lines.len(),
            self.budget_ms,
            1e3 / ms,
            self.predicted_ms,
            self.maps.0,
            self.maps.1
        );
        for (k, l) in self.lines.iter().enumerate() {
            let _ = writeln!(
                s,
                "  lamp {k:2} {:8} x{:.1}: {}{}{}",
                l.kind,
                l.intensity,
                l.pick,
                l.predicted_ms
                    .map_or(String::new(), |ms| format!(", {ms:.2} ms predicted")),
                l.device_ms
                    .map_or(String::new(), |ms| format!(", {ms:.2} ms on the device"))
            );
        }
        s
    }
}

impl Model {
    /// Adds a message line (not twice in a row), keeping the last six.
    pub(crate) fn say(&mut self, message: impl Into<String>) {
        let m = message.into();
        if self.messages.back() != Some(&m) {
            self.messages.push_back(m);
        }
        while self.messages.len() > 6 {
            self.messages.pop_front();
        }
    }
}

/// One technique's controls: technique (each offered only for the light kinds it models),
/// variant and map side.
fn technique_controls(ui: &mut egui::Ui, m: &mut Model, second: bool) {
    let kind = m.state.light.kind;
    let current = if second {
        m.state.compare.clone()
    } else {
        Some(m.state.shadow.clone())
    };
    let Some(current) = current else {
        return;
    };
    let salt = if second { "b" } else { "a" };
    let mut pick = None;
    egui::ComboBox::from_id_salt(("technique", salt))
        .selected_text(current.technique)
        .show_ui(ui, |ui| {
            for e in m.registry.families() {
                let ok = e.availability(kind);
                let r = ui
                    .add_enabled(
                        ok.is_ok(),
                        egui::Button::selectable(current.technique == e.name(), e.name()),
                    )
                    .on_disabled_hover_text(ok.err().unwrap_or_default());
                if r.clicked() {
                    pick = Some(e.name());
                }
            }
        });
    if let Some(name) = pick
        && let Err(why) = m.state.choose(second, name, &m.registry)
    {
        m.say(why);
    }
    let unavailable: Vec<String> = m
        .registry
        .families()
        .iter()
        .filter_map(|e| e.availability(kind).err())
        .collect();
    if !second && !unavailable.is_empty() {
        ui.small(format!("Not offered: {}", unavailable.join("; ")))
            .on_hover_text("a technique is offered only for the light kinds it models");
    }
    let Ok(entry) = m.registry.family(current.technique) else {
        return;
    };
    let labels: Vec<String> = entry.variants().map(|v| v.variant()).collect();
    let mut variant = current.variant.clone();
    let mut resolution = current.resolution;
    ui.horizontal(|ui| {
        egui::ComboBox::from_id_salt(("variant", salt))
            .selected_text(&variant)
            .show_ui(ui, |ui| {
                for l in &labels {
                    ui.selectable_value(&mut variant, l.clone(), l);
                }
            });
        egui::ComboBox::from_id_salt(("resolution", salt))
            .selected_text(format!("{resolution}²"))
            .show_ui(ui, |ui| {
                for r in RESOLUTIONS {
                    ui.selectable_value(&mut resolution, r, format!("{r}²"));
                }
            });
    });
    let max = entry
        .default_variant()
        .max_resolution(Backend::Gpu, m.device);
    if resolution > max {
        m.say(format!(
            "{resolution}² maps are over this device's limit for {} ({max}²): keeping {}²",
            entry.name(),
            current.resolution
        ));
        resolution = current.resolution;
    }
    let slot = if second {
        m.state.compare.as_mut()
    } else {
        Some(&mut m.state.shadow)
    };
    if let Some(slot) = slot {
        slot.variant = variant;
        slot.resolution = resolution;
    }
}

pub(crate) fn panel(ui: &mut egui::Ui, m: &mut Model, tex: egui::TextureId, tex_size: (u32, u32)) {
    egui::Panel::left("controls")
        .exact_size(PANEL_WIDTH)
        .resizable(false)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| controls(ui, m));
        });
    egui::CentralPanel::no_frame().show(ui, |ui| view(ui, m, tex, tex_size));
    let ctx = ui.ctx().clone();
    if !ctx.egui_wants_keyboard_input() {
        ctx.input(|i| {
            if i.key_pressed(egui::Key::F12) || i.key_pressed(egui::Key::P) {
                m.actions.screenshot = true;
            }
            if i.key_pressed(egui::Key::Space) {
                m.state.animate = !m.state.animate;
            }
        });
        walk(&ctx, m);
    }
}

/// W A S D or the arrow keys walk the camera (down a street, through a room) at a fifth of the
/// scene's home distance per second, Ctrl four times faster.
fn walk(ctx: &egui::Context, m: &mut Model) {
    let (forward, right, dt, fast) = ctx.input(|i| {
        let axis = |plus: [egui::Key; 2], minus: [egui::Key; 2]| {
            let down = |keys: [egui::Key; 2]| keys.iter().any(|k| i.key_down(*k));
            f32::from(down(plus)) - f32::from(down(minus))
        };
        (
            axis(
                [egui::Key::W, egui::Key::ArrowUp],
                [egui::Key::S, egui::Key::ArrowDown],
            ),
            axis(
                [egui::Key::D, egui::Key::ArrowRight],
                [egui::Key::A, egui::Key::ArrowLeft],
            ),
            i.stable_dt.min(0.1),
            i.modifiers.ctrl,
        )
    });
    if forward == 0.0 && right == 0.0 {
        return;
    }
    let speed = 0.2 * m.state.home_distance * if fast { 4.0 } else { 1.0 };
    m.state
        .camera
        .walk(forward * speed * dt, right * speed * dt);
    ctx.request_repaint();
}

fn controls(ui: &mut egui::Ui, m: &mut Model) {
    ui.heading("Scene");
    let mut open = None;
    egui::ComboBox::from_id_salt("scene")
        .selected_text(m.scene_name.clone())
        .show_ui(ui, |ui| {
            let lamps = LAMP_SCENES.map(|(name, _)| name);
            for name in SCENE_NAMES.into_iter().chain(lamps) {
                if ui.selectable_label(m.scene_name == name, name).clicked() {
                    open = Some(SceneSource::Catalogue(name.to_string()));
                }
            }
        });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut m.file_field)
                .hint_text(".glb, .gltf or .toml")
                .desired_width(PANEL_WIDTH - 80.0),
        );
        if ui.button("Open").clicked() {
            open = Some(SceneSource::File(PathBuf::from(m.file_field.trim())));
        }
    });
    ui.small("or drop a file on the window");
    if open.is_some() {
        m.actions.open = open;
    }
    ui.separator();
    if m.lamps.is_some() {
        lamps_controls(ui, m);
    } else {
        light_controls(ui, m);
    }
    view_controls(ui, m);
}

/// A scene of lamps: the frame budget they share and what it bought each.
fn lamps_controls(ui: &mut egui::Ui, m: &mut Model) {
    let Some(l) = m.lamps.as_mut() else {
        return;
    };
    ui.heading("Lamps");
    ui.add(
        egui::Slider::new(&mut l.budget_ms, 1.0..=10_000.0)
            .logarithmic(true)
            .text("frame budget, ms"),
    );
    let device: Vec<f64> = l.lines.iter().filter_map(|x| x.device_ms).collect();
    let device = if device.is_empty() {
        String::new()
    } else {
        format!(", {:.2} on the device", device.iter().sum::<f64>())
    };
    ui.small(format!(
        "{:.2} ms predicted{device}; {} maps made, {} kept last frame",
        l.predicted_ms, l.maps.0, l.maps.1
    ));
    egui::Grid::new("lamps").striped(true).show(ui, |ui| {
        for (k, line) in l.lines.iter().enumerate() {
            ui.label(format!("{k} {} x{:.1}", line.kind, line.intensity));
            ui.small(&line.pick);
            ui.end_row();
        }
    });
    ui.checkbox(&mut m.state.animate, "swing a lamp (space)");
    ui.small("W A S D walk the camera; the budget picks each lamp's technique and map side");
    ui.separator();
}

/// One light: its kind, place and size, and the technique (or two) that shadows it.
fn light_controls(ui: &mut egui::Ui, m: &mut Model) {
    ui.heading("Light");
    let mut kind = m.state.light.kind;
    egui::ComboBox::from_id_salt("light kind")
        .selected_text(kind.name())
        .show_ui(ui, |ui| {
            for k in LightKind::ALL {
                ui.selectable_value(&mut kind, k, k.name());
            }
        });
    if kind != m.state.light.kind {
        let registry = std::mem::take(&mut m.registry);
        for line in m.state.set_light_kind(kind, &registry) {
            m.say(line);
        }
        m.registry = registry;
    }
    let mut distance = m.state.light.distance();
    ui.add(
        egui::Slider::new(&mut distance, 0.5..=20.0)
            .logarithmic(true)
            .text("distance"),
    );
    if (distance - m.state.light.distance()).abs() > 1e-4 {
        m.state.light.set_distance(distance);
    }
    let d = m.state.light.distance();
    ui.add(
        egui::Slider::new(&mut m.state.light.size, SIZE_RANGE.0 * d..=SIZE_RANGE.1 * d)
            .logarithmic(true)
            .text("size"),
    );
    ui.checkbox(&mut m.state.animate, "animate (space)");
    ui.small("drag with the right button in the view to move the light; W A S D walk");
    ui.separator();
    ui.heading("Technique");
    technique_controls(ui, m, false);
    let mut compare = m.state.compare.is_some();
    ui.checkbox(&mut compare, "compare with a second technique");
    if compare != m.state.compare.is_some() {
        m.state.compare = compare.then(|| m.state.shadow.clone());
    }
    if m.state.compare.is_some() {
        technique_controls(ui, m, true);
        ui.add(egui::Slider::new(&mut m.state.split, 0.0..=1.0).text("split"));
    }
    ui.separator();
}

/// The view mode, the times and the messages.
fn view_controls(ui: &mut egui::Ui, m: &mut Model) {
    ui.heading("View");
    ui.horizontal(|ui| {
        for (mode, label) in [
            (ViewMode::Shaded, "shaded"),
            (ViewMode::Visibility, "V"),
            (ViewMode::Error, "error"),
            (ViewMode::Views, "views"),
        ] {
            if m.lamps.is_none() || crate::lamps::MODES.contains(&mode) {
                ui.radio_value(&mut m.state.mode, mode, label);
            }
        }
    });
    if m.state.mode == ViewMode::Error {
        ui.small("red: darker than the reference; blue: lighter");
        ui.label(&m.reference_status);
    }
    ui.separator();
    ui.heading("Time");
    let s = &m.stats;
    let last = s.frame_ms.back().copied().unwrap_or(0.0);
    ui.label(format!(
        "frame {last:.1} ms ({:.0} fps)",
        1e3 / last.max(1e-3)
    ));
    let p = s.passes;
    let gpu = match (m.timestamps, s.gpu_ms) {
        (true, Some(g)) => g.map(|t| format!("{t:.2}")),
        (true, None) => [
            "waiting".to_string(),
            String::new(),
            String::new(),
            String::new(),
        ],
        (false, _) => [
            "no timestamps".to_string(),
            String::new(),
            String::new(),
            String::new(),
        ],
    };
    egui::Grid::new("passes").striped(true).show(ui, |ui| {
        ui.label("ms");
        ui.label("CPU");
        ui.label("GPU");
        ui.end_row();
        for (k, (name, cpu)) in [
            ("G-buffer", p.gbuffer),
            ("technique", p.technique),
            ("compared", p.compare),
            ("shading", p.shade),
        ]
        .into_iter()
        .enumerate()
        {
            ui.label(name);
            ui.label(format!("{cpu:.2}"));
            ui.label(&gpu[k]);
            ui.end_row();
        }
    });
    frame_graph(ui, &s.frame_ms);
    if ui.button("Screenshot (F12)").clicked() {
        m.actions.screenshot = true;
    }
    if let Some(l) = &m.lost {
        ui.colored_label(egui::Color32::RED, l);
    }
    for line in m.messages.iter().rev() {
        ui.colored_label(egui::Color32::from_rgb(230, 180, 80), line);
    }
}

fn frame_graph(ui: &mut egui::Ui, frames: &VecDeque<f32>) {
    let (rect, _) =
        ui.allocate_exact_size(egui::vec2(ui.available_width(), 60.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(30));
    let top = frames.iter().copied().fold(33.3f32, f32::max);
    let n = frames.len().max(2) as f32;
    let points: Vec<egui::Pos2> = frames
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            egui::pos2(
                rect.left() + rect.width() * i as f32 / (n - 1.0),
                rect.bottom() - rect.height() * (t / top).min(1.0),
            )
        })
        .collect();
    let y16 = rect.bottom() - rect.height() * 16.7 / top;
    painter.hline(rect.x_range(), y16, (1.0, egui::Color32::from_gray(80)));
    painter.add(egui::Shape::line(points, (1.5, egui::Color32::LIGHT_GREEN)));
    painter.text(
        rect.left_top(),
        egui::Align2::LEFT_TOP,
        format!("{top:.0} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::GRAY,
    );
}

fn view(ui: &mut egui::Ui, m: &mut Model, tex: egui::TextureId, tex_size: (u32, u32)) {
    let rect = ui.available_rect_before_wrap();
    let ppp = ui.ctx().pixels_per_point();
    let min = (rect.min.to_vec2() * ppp).round();
    let max = (rect.max.to_vec2() * ppp).round();
    m.view_origin_px = (min.x as u32, min.y as u32);
    m.view_px = (
        (max.x - min.x).max(1.0) as u32,
        (max.y - min.y).max(1.0) as u32,
    );
    let image = egui::Rect::from_min_size(
        (min / ppp).to_pos2(),
        egui::vec2(tex_size.0 as f32, tex_size.1 as f32) / ppp,
    );
    ui.painter().image(
        tex,
        image,
        egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
        egui::Color32::WHITE,
    );
    let response = ui.interact(
        rect,
        ui.scope_id().with("3d view"),
        egui::Sense::click_and_drag(),
    );
    let delta = response.drag_delta() * ppp;
    let shift = ui.ctx().input(|i| i.modifiers.shift);
    let home = m.state.home_distance;
    let s = &mut m.state;
    if response.dragged_by(egui::PointerButton::Primary) && !shift {
        s.camera.orbit(delta.x, delta.y);
    } else if response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && shift)
    {
        s.camera.pan(delta.x, delta.y, m.view_px.1 as f32);
    } else if response.dragged_by(egui::PointerButton::Secondary) {
        // Across and into the screen, in the horizontal plane.
        let (sy, cy) = s.camera.yaw.sin_cos();
        let k = 0.004 * s.light.distance();
        let (dx, dz) = (delta.x * cy - delta.y * sy, -delta.x * sy - delta.y * cy);
        s.light.drag(dx * k, dz * k);
    }
    if response.hovered() {
        let scroll = ui.ctx().input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            s.camera.zoom(scroll / 40.0, home);
        }
    }
}

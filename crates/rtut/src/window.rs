//! RTUT's window: an eframe window that fills itself with the last frame `rtutSwapBuffers`
//! rendered, at the window's size in pixels, and turns the window's events into the program's
//! callbacks, as GLUT calls them: reshape when the size changes, display when a redisplay is
//! posted, keyboard and mouse on input, idle when nothing else is due.

use std::ffi::{c_int, c_uchar};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use eframe::egui::{self, Color32, ColorImage, Event, Key, PointerButton, Pos2, Rect, TextureHandle, TextureOptions};

use crate::rt::Error;
use crate::state::{Callbacks, with};
use crate::{RTUT_DOWN, RTUT_LEFT_BUTTON, RTUT_MIDDLE_BUTTON, RTUT_RIGHT_BUTTON, RTUT_UP};

/// Runs the window titled `title`, `size` pixels inside, until it closes.
pub(super) fn run(title: String, size: (u32, u32), screenshot: Option<PathBuf>) -> Result<(), Error> {
    let shot: Arc<Mutex<Option<Arc<ColorImage>>>> = Arc::default();
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_title(title.clone()).with_inner_size([size.0 as f32, size.1 as f32]),
        ..eframe::NativeOptions::default()
    };
    let app = Window { texture: None, shown: u64::MAX, screenshot: screenshot.as_ref().map(|_| Shot::Waiting(Arc::clone(&shot))) };
    eframe::run_native(&title, options, Box::new(move |_| Ok(Box::new(app)))).map_err(|e| Error::internal(format!("the window failed: {e}")))?;
    let (Some(path), Some(image)) = (screenshot, shot.lock().unwrap_or_else(|e| e.into_inner()).take()) else { return Ok(()) };
    let [width, height] = image.size;
    let rgba: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    image::save_buffer(&path, &rgba, width as u32, height as u32, image::ExtendedColorType::Rgba8)
        .map_err(|e| Error::io(format!("cannot write the screenshot {}: {e}", path.display())))
}

/// A screenshot of the window asked for by `RTUT_SCREENSHOT`.
enum Shot {
    /// To be taken once a frame is on screen, into the slot.
    Waiting(Arc<Mutex<Option<Arc<ColorImage>>>>),
    Taken,
}

struct Window {
    texture: Option<TextureHandle>,
    /// The count of frames swapped when the texture was last filled.
    shown: u64,
    screenshot: Option<Shot>,
}

impl Window {
    /// Calls the callbacks the window's state calls for, in GLUT's order: reshape, input, then
    /// display or idle.
    fn callbacks(&mut self, ctx: &egui::Context, pixels: (u32, u32)) {
        let (callbacks, resized) = with(|r| {
            let resized = r.frame_size() != pixels;
            if resized {
                r.resize(pixels.0, pixels.1);
                r.redisplay = true;
            }
            (r.callbacks, resized)
        });
        let Callbacks { display, reshape, keyboard, mouse, idle } = callbacks;
        // SAFETY (every call below): callbacks the program registered, called as GLUT calls them,
        // on the thread of its main loop, with no state of raystage's borrowed.
        if resized && let Some(reshape) = reshape {
            unsafe { reshape(pixels.0 as c_int, pixels.1 as c_int) };
        }
        let scale = ctx.pixels_per_point();
        let at = |p: Pos2| ((p.x * scale).round() as c_int, (p.y * scale).round() as c_int);
        let pointer = ctx.input(|i| i.pointer.latest_pos()).map_or((0, 0), at);
        for event in ctx.input(|i| i.events.clone()) {
            match event {
                Event::Text(text) => {
                    if let Some(keyboard) = keyboard {
                        for byte in text.bytes().filter(u8::is_ascii) {
                            unsafe { keyboard(byte as c_uchar, pointer.0, pointer.1) };
                        }
                    }
                }
                Event::Key { key, pressed: true, .. } => {
                    if let (Some(keyboard), Some(code)) = (keyboard, control_code(key)) {
                        unsafe { keyboard(code, pointer.0, pointer.1) };
                    }
                }
                Event::PointerButton { pos, button, pressed, .. } => {
                    if let (Some(mouse), Some(button)) = (mouse, button_code(button)) {
                        let (x, y) = at(pos);
                        unsafe { mouse(button, if pressed { RTUT_DOWN } else { RTUT_UP }, x, y) };
                    }
                }
                _ => {}
            }
        }
        let redisplay = with(|r| std::mem::take(&mut r.redisplay));
        match (redisplay, display, idle) {
            (true, Some(display), _) => unsafe { display() },
            (_, _, Some(idle)) => unsafe { idle() },
            _ => {}
        }
    }

    /// With `RTUT_SCREENSHOT`: once a frame has been painted, asks for a screenshot.
    fn screenshot(&mut self, ctx: &egui::Context) {
        if let Some(Shot::Waiting(slot)) = &self.screenshot
            && self.texture.is_some()
        {
            let (slot, waker) = (Arc::clone(slot), ctx.clone());
            ctx.request_screenshot(move |image| {
                *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(image);
                waker.request_repaint();
            });
            self.screenshot = Some(Shot::Taken);
        }
    }
}

impl eframe::App for Window {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        let rect = ctx.content_rect();
        let scale = ctx.pixels_per_point();
        let pixels = (((rect.width() * scale).round() as u32).max(1), ((rect.height() * scale).round() as u32).max(1));
        self.callbacks(&ctx, pixels);

        // The last frame swapped, uploaded once.
        let (swapped, leave, busy) = with(|r| (r.swapped, r.leave, r.redisplay || r.callbacks.idle.is_some()));
        if swapped != self.shown && swapped > 0 {
            let image = with(|r| {
                let ((width, height), rgba) = r.shown();
                ColorImage::from_rgba_unmultiplied([width as usize, height as usize], rgba)
            });
            match &mut self.texture {
                Some(texture) => texture.set(image, TextureOptions::NEAREST),
                None => self.texture = Some(ctx.load_texture("rtut-frame", image, TextureOptions::NEAREST)),
            }
            self.shown = swapped;
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let area = ui.max_rect();
            ui.painter().rect_filled(area, 0.0, Color32::BLACK);
            if let Some(texture) = &self.texture {
                // The frame at its own pixels, from the top left (it lags a resize by one frame).
                let size = texture.size_vec2() / scale;
                ui.painter().image(texture.id(), Rect::from_min_size(area.min, size), Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0)), Color32::WHITE);
            }
        });
        self.screenshot(&ctx);
        if leave {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        } else if busy {
            ctx.request_repaint();
        }
    }
}

/// The ASCII code GLUT's keyboard callback gets for a key that types no text.
fn control_code(key: Key) -> Option<c_uchar> {
    Some(match key {
        Key::Escape => 27,
        Key::Enter => 13,
        Key::Backspace => 8,
        Key::Tab => 9,
        Key::Delete => 127,
        _ => return None,
    })
}

/// GLUT's code of a mouse button.
fn button_code(button: PointerButton) -> Option<c_int> {
    match button {
        PointerButton::Primary => Some(RTUT_LEFT_BUTTON),
        PointerButton::Middle => Some(RTUT_MIDDLE_BUTTON),
        PointerButton::Secondary => Some(RTUT_RIGHT_BUTTON),
        _ => None,
    }
}

//! What a frame says besides the discs: the time in its top-left corner and, in its
//! top-right, the key to the colouring in use (a ramp with its ends for speed, radius and
//! spin; a swatch and a name for each of the scenario's colours). Text is drawn with the
//! same TrueType font as `plots.png`; without one, frames go without text.

use ab_glyph::{Font, FontVec, PxScale, ScaleFont, point};
use bounce_scenario::palette::Palette;
use bounce_scenario::{ColorBy, Rgb, ramp, spin_ramp};
use tiny_skia::{Paint, Pixmap, PremultipliedColorU8, Rect, Transform};

/// The text's colour, and the translucent panel behind it.
const INK: Rgb = [235, 238, 245];
const PANEL: Rgb = [0, 0, 0];
/// The most named colours a key lists.
const MAX_SWATCHES: usize = 8;

/// The overlay's font and what its key shows.
pub struct Overlay {
    font: FontVec,
    key: Key,
}

/// The key to a colouring.
enum Key {
    /// A ramp from `ends.0` to `ends.1` of the quantity `what`.
    Ramp {
        what: &'static str,
        ends: (f64, f64),
        colour: fn(f64) -> Rgb,
    },
    /// Named colours.
    Swatches(Vec<(Rgb, String)>),
}

impl Overlay {
    /// The overlay for `palette`; `named` lists the scenario's colours with their names
    /// (used when colouring by them). `None` where no font is installed.
    pub fn new(palette: &Palette, named: Vec<(Rgb, String)>) -> Option<Overlay> {
        let font = crate::font::bytes().and_then(|bytes| FontVec::try_from_vec(bytes).ok())?;
        let key = match palette.colour_by {
            ColorBy::Speed => Key::Ramp {
                what: "speed",
                ends: (0.0, palette.speed_scale),
                colour: ramp,
            },
            ColorBy::Radius => Key::Ramp {
                what: "radius",
                ends: (palette.radius_range[0], palette.radius_range[1]),
                colour: ramp,
            },
            ColorBy::Spin => Key::Ramp {
                what: "spin",
                ends: (-palette.spin_scale, palette.spin_scale),
                colour: |t| spin_ramp(2.0 * t - 1.0),
            },
            ColorBy::Color => Key::Swatches(named.into_iter().take(MAX_SWATCHES).collect()),
        };
        Some(Overlay { font, key })
    }

    /// Writes the time and the key onto a frame.
    pub fn draw(&self, pixmap: &mut Pixmap, time: f64) {
        let px = (pixmap.width() as f32 / 45.0).clamp(13.0, 24.0);
        let pad = (px * 0.4).round();
        let line = (px * 1.3).round();
        // The time, top left.
        let label = format!("t = {}", short(time));
        let width = self.width(&label, px);
        panel(pixmap, 0.0, 0.0, width + 2.0 * pad, line + pad);
        self.text(pixmap, &label, px, pad, pad + px * 0.9);
        // The key, top right.
        let right = pixmap.width() as f32;
        match &self.key {
            Key::Ramp { what, ends, colour } => {
                let (lo, hi) = (short(ends.0), short(ends.1));
                let bar = (px * 6.0).round();
                let (lo_w, hi_w, what_w) = (
                    self.width(&lo, px),
                    self.width(&hi, px),
                    self.width(what, px),
                );
                let total = what_w + lo_w + bar + hi_w + 4.0 * pad;
                let x0 = right - total - pad;
                panel(pixmap, x0, 0.0, total + pad, line + pad);
                let baseline = pad + px * 0.9;
                let mut x = x0 + pad;
                self.text(pixmap, what, px, x, baseline);
                x += what_w + pad;
                self.text(pixmap, &lo, px, x, baseline);
                x += lo_w + pad;
                for k in 0..bar as u32 {
                    let c = colour(k as f64 / (bar as f64 - 1.0).max(1.0));
                    fill(pixmap, x + k as f32, pad, 1.0, px, c);
                }
                x += bar + pad;
                self.text(pixmap, &hi, px, x, baseline);
            }
            Key::Swatches(named) if !named.is_empty() => {
                let widest = named
                    .iter()
                    .map(|(_, name)| self.width(name, px))
                    .fold(0.0, f32::max);
                let total = px + pad + widest + 2.0 * pad;
                let x0 = right - total - pad;
                panel(
                    pixmap,
                    x0,
                    0.0,
                    total + pad,
                    named.len() as f32 * line + pad,
                );
                for (k, (colour, name)) in named.iter().enumerate() {
                    let top = pad + k as f32 * line;
                    fill(pixmap, x0 + pad, top, px, px, *colour);
                    self.text(pixmap, name, px, x0 + 2.0 * pad + px, top + px * 0.9);
                }
            }
            Key::Swatches(_) => {}
        }
    }

    /// How wide `text` is at `px` pixels.
    fn width(&self, text: &str, px: f32) -> f32 {
        let scaled = self.font.as_scaled(PxScale::from(px));
        text.chars()
            .map(|c| scaled.h_advance(scaled.glyph_id(c)))
            .sum()
    }

    /// `text` at `px` pixels from `x` on the baseline `y`, in [`INK`].
    fn text(&self, pixmap: &mut Pixmap, text: &str, px: f32, x: f32, y: f32) {
        let scaled = self.font.as_scaled(PxScale::from(px));
        let mut caret = x;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            let glyph = id.with_scale_and_position(px, point(caret, y));
            caret += scaled.h_advance(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                outline.draw(|gx, gy, coverage| {
                    let (px_x, px_y) = (
                        bounds.min.x as i64 + gx as i64,
                        bounds.min.y as i64 + gy as i64,
                    );
                    blend(pixmap, px_x, px_y, INK, coverage);
                });
            }
        }
    }
}

/// A number as a label: short, with no trailing zeros.
fn short(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-2..1e5).contains(&a) {
        let text = format!("{v:.2}");
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

/// A translucent dark panel behind text.
fn panel(pixmap: &mut Pixmap, x: f32, y: f32, w: f32, h: f32) {
    if let Some(rect) = Rect::from_xywh(x, y, w, h) {
        let mut paint = Paint::default();
        paint.set_color_rgba8(PANEL[0], PANEL[1], PANEL[2], 150);
        pixmap.fill_rect(rect, &paint, Transform::identity(), None);
    }
}

/// An opaque rectangle on whole pixels (an anti-aliased one-pixel column of the ramp would
/// mix with its neighbours and the panel).
fn fill(pixmap: &mut Pixmap, x: f32, y: f32, w: f32, h: f32, colour: Rgb) {
    if let Some(rect) = Rect::from_xywh(x.round(), y.round(), w.round(), h.round()) {
        let mut paint = Paint {
            anti_alias: false,
            ..Paint::default()
        };
        paint.set_color_rgba8(colour[0], colour[1], colour[2], 255);
        pixmap.fill_rect(rect, &paint, Transform::identity(), None);
    }
}

/// Mixes `colour` into the opaque pixel at `(x, y)` by `coverage`.
fn blend(pixmap: &mut Pixmap, x: i64, y: i64, colour: Rgb, coverage: f32) {
    let (w, h) = (pixmap.width() as i64, pixmap.height() as i64);
    if !(0..w).contains(&x) || !(0..h).contains(&y) {
        return;
    }
    let pixel = &mut pixmap.pixels_mut()[(y * w + x) as usize];
    let c = coverage.clamp(0.0, 1.0);
    let mix = |old: u8, new: u8| (old as f32 + (new as f32 - old as f32) * c).round() as u8;
    let mixed = [
        mix(pixel.red(), colour[0]),
        mix(pixel.green(), colour[1]),
        mix(pixel.blue(), colour[2]),
    ];
    if let Some(p) = PremultipliedColorU8::from_rgba(mixed[0], mixed[1], mixed[2], 255) {
        *pixel = p;
    }
}

#[cfg(test)]
mod tests {
    use super::short;

    #[test]
    fn labels_are_short() {
        assert_eq!(short(12.5), "12.5");
        assert_eq!(short(3.0), "3");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(1234567.0), "1.2e6");
    }
}

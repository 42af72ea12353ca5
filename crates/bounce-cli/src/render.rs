//! Pictures of the world: PNG frames with discs to scale, and an animated GIF.

use std::path::Path;

use anyhow::{Context, Result};
use bounce::{Shape, World};
use bounce_scenario::palette::Palette;
use bounce_scenario::{ColorBy, Rgb};
use tiny_skia::{
    Color, FillRule, FilterQuality, Paint, PathBuilder, Pixmap, PixmapPaint, Rect, Stroke,
    Transform,
};

use bounce_scenario::atomic::AtomicFile;

const BACKGROUND: Rgb = [17, 20, 26];
/// The walls, light on the dark background so that they stand out.
const BOX_EDGE: Rgb = [200, 205, 215];
/// GIF frames are at most this wide, to keep the file small.
const GIF_WIDTH: u32 = 480;

/// What a frame shows and how it colours discs.
pub struct Painter {
    min: [f64; 2],
    max: [f64; 2],
    width: u32,
    height: u32,
    palette: Palette,
    /// Each obstacle's colour.
    obstacle_colours: Vec<Rgb>,
    /// The time and the colour key, written on each frame.
    overlay: Option<crate::overlay::Overlay>,
}

impl Painter {
    /// A painter for the region `view` (the session's) at `width` pixels, colouring with
    /// scales fixed from the world as it is now.
    pub fn new(
        world: &World,
        (min, max): ([f64; 2], [f64; 2]),
        width: u32,
        colour_by: ColorBy,
        colours: Vec<Option<Rgb>>,
    ) -> Self {
        let aspect = (max[1] - min[1]) / (max[0] - min[0]);
        let height = ((width as f64 * aspect).round() as u32).clamp(16, 8192);
        Painter {
            min,
            max,
            width,
            height,
            palette: Palette::for_world(world, colour_by, colours),
            obstacle_colours: Vec::new(),
            overlay: None,
        }
    }

    /// Writes the time and a key to the colouring on each frame; `named` gives the
    /// scenario's colours their names, for colouring by them.
    pub fn with_key(mut self, named: Vec<(Rgb, String)>) -> Self {
        self.overlay = crate::overlay::Overlay::new(&self.palette, named);
        self
    }

    /// Colours disc `id` (a disc an emitter added) with `colour`.
    pub fn set_colour(&mut self, id: usize, colour: Option<Rgb>) {
        let colours = &mut self.palette.colours;
        if colours.len() <= id {
            colours.resize(id + 1, None);
        }
        colours[id] = colour;
    }

    /// Draws the obstacles in these colours (one per obstacle; grey where missing).
    pub fn with_obstacle_colours(mut self, colours: Vec<Rgb>) -> Self {
        self.obstacle_colours = colours;
        self
    }

    /// Frame size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// World coordinates to pixels (y up in the world, down in the image), in `f64`: far
    /// shapes are clipped to the picture before the rasteriser's `f32`.
    pub fn to_pixel(&self, x: f64, y: f64) -> (f64, f64) {
        let sx = self.width as f64 / (self.max[0] - self.min[0]);
        let sy = self.height as f64 / (self.max[1] - self.min[1]);
        ((x - self.min[0]) * sx, (self.max[1] - y) * sy)
    }

    /// [`Painter::to_pixel`] for a point the rasteriser may take as it is (the box's corners).
    fn to_pixel_f32(&self, x: f64, y: f64) -> (f32, f32) {
        let (x, y) = self.to_pixel(x, y);
        (x as f32, y as f32)
    }

    /// Draws the world.
    pub fn paint(&self, world: &World) -> Pixmap {
        let mut pixmap = Pixmap::new(self.width, self.height).expect("size checked");
        pixmap.fill(rgb(BACKGROUND));
        let scale = self.width as f64 / (self.max[0] - self.min[0]);
        if let Some((min, max)) = world.config().boundary.bounds() {
            let (x0, y0) = self.to_pixel_f32(min[0], max[1]);
            let (x1, y1) = self.to_pixel_f32(max[0], min[1]);
            if let Some(rect) = Rect::from_ltrb(x0 + 1.0, y0 + 1.0, x1 - 1.0, y1 - 1.0) {
                let mut paint = Paint::default();
                paint.set_color(rgb(BOX_EDGE));
                let path = PathBuilder::from_rect(rect);
                let stroke = Stroke {
                    width: 2.0,
                    ..Stroke::default()
                };
                pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
            }
        }
        self.paint_regions(world, &mut pixmap);
        self.paint_obstacles(world, &mut pixmap, scale);
        let p = world.particles();
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        let (width, height) = (self.width as f64, self.height as f64);
        // In id order: overlapping discs are drawn the same way whatever the storage order.
        for (_, i) in world.in_id_order() {
            let (x, y) = self.to_pixel(p.x()[i], p.y()[i]);
            let r = p.radius()[i] * scale;
            // Only discs that reach into the picture: a frame of a small view of a large
            // world draws a few thousand of its million discs.
            if !(x + r >= 0.0 && x - r <= width && y + r >= 0.0 && y - r <= height) {
                continue;
            }
            let speed = p.vx()[i].hypot(p.vy()[i]);
            let spin = p.angular_velocity().get(i).copied().unwrap_or(0.0);
            let colour = self
                .palette
                .colour(p.ids()[i].0 as usize, speed, p.radius()[i], spin);
            paint.set_color(rgb(colour));
            if r < 0.75 {
                // Smaller than a pixel: one pixel, so a million discs stay visible and fast.
                if let Some(rect) = Rect::from_xywh(x.floor() as f32, y.floor() as f32, 1.0, 1.0) {
                    pixmap.fill_rect(rect, &paint, Transform::identity(), None);
                }
            } else {
                fill_circle(&mut pixmap, x, y, r, &paint);
                if let Some(&theta) = p.orientation().get(i)
                    && r >= 2.0
                {
                    // Where the disc has turned: a radius in a darker shade.
                    let tip = (x + r * theta.cos(), y - r * theta.sin());
                    paint.set_color(rgb(colour.map(|c| (c as f64 * 0.4) as u8)));
                    let mut path = PathBuilder::new();
                    path.move_to(x as f32, y as f32);
                    path.line_to(tip.0 as f32, tip.1 as f32);
                    if let Some(path) = path.finish() {
                        let stroke = Stroke {
                            width: (r / 6.0).clamp(1.0, 3.0) as f32,
                            ..Stroke::default()
                        };
                        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
                    }
                }
            }
        }
        if let Some(overlay) = &self.overlay {
            overlay.draw(&mut pixmap, world.time());
        }
        pixmap
    }
}

/// Emitter regions are outlined in this colour, sinks in [`SINK`].
const EMITTER: Rgb = [90, 170, 110];
const SINK: Rgb = [190, 90, 90];

impl Painter {
    /// The outlines of the emitters' and the sinks' regions.
    fn paint_regions(&self, world: &World, pixmap: &mut Pixmap) {
        let config = world.config();
        let regions = config
            .emitters
            .iter()
            .map(|e| (e.min, e.max, EMITTER))
            .chain(config.sinks.iter().map(|s| (s.min, s.max, SINK)));
        let mut paint = Paint::default();
        for (min, max, colour) in regions {
            let (x0, y0) = self.to_pixel_f32(min[0], max[1]);
            let (x1, y1) = self.to_pixel_f32(max[0], min[1]);
            if let Some(rect) = Rect::from_ltrb(x0, y0, x1, y1) {
                paint.set_color(rgb(colour));
                let path = PathBuilder::from_rect(rect);
                pixmap.stroke_path(
                    &path,
                    &paint,
                    &Stroke::default(),
                    Transform::identity(),
                    None,
                );
            }
        }
    }

    /// Segments as lines (2 pixels wide), pegs as discs to scale.
    fn paint_obstacles(&self, world: &World, pixmap: &mut Pixmap, scale: f64) {
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        let stroke = Stroke {
            width: 2.0,
            line_cap: tiny_skia::LineCap::Round,
            ..Stroke::default()
        };
        for (k, shape) in world.obstacle_shapes().iter().enumerate() {
            let colour = self
                .obstacle_colours
                .get(k)
                .copied()
                .unwrap_or(bounce_scenario::OBSTACLE_GREY);
            paint.set_color(rgb(colour));
            match *shape {
                Shape::Segment { a, b } => {
                    let size = (self.width as f64, self.height as f64);
                    let Some([(x0, y0), (x1, y1)]) =
                        clip_segment(self.to_pixel(a[0], a[1]), self.to_pixel(b[0], b[1]), size)
                    else {
                        continue;
                    };
                    let mut path = PathBuilder::new();
                    path.move_to(x0, y0);
                    path.line_to(x1, y1);
                    if let Some(path) = path.finish() {
                        pixmap.stroke_path(&path, &paint, &stroke, Transform::identity(), None);
                    }
                }
                Shape::Peg { centre, radius } => {
                    let (x, y) = self.to_pixel(centre[0], centre[1]);
                    fill_circle(pixmap, x, y, (radius * scale).max(0.75), &paint);
                }
            }
        }
    }
}

/// Beyond this many pixels from the picture, or this large, shapes are clipped to it here:
/// the rasteriser's fixed-point coordinates overflow far out (and panic).
const RASTER_LIMIT: f64 = 4096.0;

/// A filled circle of radius `r` pixels at `(x, y)`, of any size and place: nothing where
/// it misses the picture; a large or far one as the exact spans of its pixel rows.
fn fill_circle(pixmap: &mut Pixmap, x: f64, y: f64, r: f64, paint: &Paint) {
    let (width, height) = (pixmap.width() as f64, pixmap.height() as f64);
    if !(x + r >= 0.0 && x - r <= width && y + r >= 0.0 && y - r <= height) {
        return;
    }
    let near = |v: f64, size: f64| v.abs() <= RASTER_LIMIT + size;
    if r <= RASTER_LIMIT && near(x, width) && near(y, height) {
        if let Some(path) = PathBuilder::from_circle(x as f32, y as f32, r as f32) {
            pixmap.fill_path(&path, paint, FillRule::Winding, Transform::identity(), None);
        }
        return;
    }
    let (cx, cy) = (x, y);
    for row in 0..pixmap.height() {
        let dy = row as f64 + 0.5 - cy;
        if dy.abs() > r {
            continue;
        }
        let half = (r * r - dy * dy).sqrt();
        let (left, right) = ((cx - half).max(0.0), (cx + half).min(width));
        if let Some(rect) = Rect::from_ltrb(left as f32, row as f32, right as f32, row as f32 + 1.0)
        {
            pixmap.fill_rect(rect, paint, Transform::identity(), None);
        }
    }
}

/// The part of the segment from `a` to `b` (pixels) within [`RASTER_LIMIT`] of a picture
/// of `size` (Liang–Barsky), if any.
fn clip_segment(a: (f64, f64), b: (f64, f64), size: (f64, f64)) -> Option<[(f32, f32); 2]> {
    let (lo, hi) = (
        -RASTER_LIMIT,
        [size.0 + RASTER_LIMIT, size.1 + RASTER_LIMIT],
    );
    let (x0, y0, dx, dy) = (a.0, a.1, b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // Which side clipped each end: that coordinate is then the side's, exactly (`t` of a
    // long segment carries its length's rounding).
    let (mut side0, mut side1) = (None, None);
    let sides = [(0, lo), (0, hi[0]), (1, lo), (1, hi[1])];
    for (k, (p, q)) in [
        (-dx, x0 - lo),
        (dx, hi[0] - x0),
        (-dy, y0 - lo),
        (dy, hi[1] - y0),
    ]
    .into_iter()
    .enumerate()
    {
        if !(p.is_finite() && q.is_finite()) {
            return None;
        }
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 && t > t0 {
                (t0, side0) = (t, Some(sides[k]));
            } else if p > 0.0 && t < t1 {
                (t1, side1) = (t, Some(sides[k]));
            }
        }
    }
    (t0 <= t1).then(|| {
        let at = |t: f64, side: Option<(usize, f64)>| {
            let mut point = [x0 + t * dx, y0 + t * dy];
            if let Some((axis, v)) = side {
                point[axis] = v;
            }
            (point[0] as f32, point[1] as f32)
        };
        [at(t0, side0), at(t1, side1)]
    })
}

fn rgb(c: Rgb) -> Color {
    Color::from_rgba8(c[0], c[1], c[2], 255)
}

/// Writes a frame as PNG, atomically.
pub fn save_png(pixmap: &Pixmap, path: &Path) -> Result<()> {
    let bytes = pixmap
        .encode_png()
        .with_context(|| format!("cannot encode {}", path.display()))?;
    Ok(bounce_scenario::atomic::write(path, &bytes)?)
}

/// An animated GIF built frame by frame.
pub struct GifWriter {
    encoder: gif::Encoder<AtomicFile>,
    width: u32,
    height: u32,
}

impl GifWriter {
    /// Starts `path` for frames of `size` (scaled down to at most 480 pixels wide).
    pub fn create(path: &Path, size: (u32, u32)) -> Result<Self> {
        let scale = (GIF_WIDTH as f64 / size.0 as f64).min(1.0);
        let width = ((size.0 as f64 * scale).round() as u32).max(1);
        let height = ((size.1 as f64 * scale).round() as u32).max(1);
        let file = AtomicFile::create(path)?;
        let mut encoder = gif::Encoder::new(file, width as u16, height as u16, &[])
            .context("cannot start the GIF")?;
        encoder.set_repeat(gif::Repeat::Infinite)?;
        Ok(GifWriter {
            encoder,
            width,
            height,
        })
    }

    /// Adds a frame.
    pub fn add(&mut self, pixmap: &Pixmap) -> Result<()> {
        let mut small = Pixmap::new(self.width, self.height).expect("size checked");
        let sx = self.width as f32 / pixmap.width() as f32;
        let sy = self.height as f32 / pixmap.height() as f32;
        let paint = PixmapPaint {
            quality: FilterQuality::Bilinear,
            ..PixmapPaint::default()
        };
        small.draw_pixmap(
            0,
            0,
            pixmap.as_ref(),
            &paint,
            Transform::from_scale(sx, sy),
            None,
        );
        let mut rgba = small.take();
        let mut frame =
            gif::Frame::from_rgba_speed(self.width as u16, self.height as u16, &mut rgba, 20);
        frame.delay = 6; // hundredths of a second
        self.encoder
            .write_frame(&frame)
            .context("cannot write a GIF frame")?;
        Ok(())
    }

    /// Completes the file.
    pub fn finish(self) -> Result<()> {
        let file = self.encoder.into_inner().context("cannot finish the GIF")?;
        Ok(file.commit()?)
    }
}

/// The frame PNGs in `dir` (`frame_STEP.png`) with their steps, in step order.
pub fn frame_files(dir: &Path) -> Vec<(u64, std::path::PathBuf)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut frames: Vec<(u64, std::path::PathBuf)> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| {
            let name = e.file_name().into_string().ok()?;
            let step = name
                .strip_prefix("frame_")?
                .strip_suffix(".png")?
                .parse()
                .ok()?;
            Some((step, e.path()))
        })
        .collect();
    frames.sort();
    frames
}

/// Writes `path`, an animated GIF of the PNG `frames` (of `size` pixels), in order.
pub fn gif_from_frames(
    frames: &[(u64, std::path::PathBuf)],
    size: (u32, u32),
    path: &Path,
) -> Result<()> {
    let mut gif = GifWriter::create(path, size)?;
    for (_, frame) in frames {
        let pixmap = Pixmap::load_png(frame)
            .with_context(|| format!("cannot read the frame {}", frame.display()))?;
        gif.add(&pixmap)?;
    }
    gif.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bounce::{Config, Particle};

    /// The painted pixels of `discs` in the view `[0, 10]²` at 100 pixels, with a blue
    /// scenario colour for every disc.
    fn painted(discs: &[([f64; 2], f64)]) -> Vec<bool> {
        let mut world = World::new(Config::default()).unwrap();
        for &(position, radius) in discs {
            world
                .add_particle(Particle::new(position, [0.0, 0.0], radius))
                .unwrap();
        }
        let colours = vec![Some([0, 0, 255]); discs.len()];
        let painter = Painter::new(
            &world,
            ([0.0, 0.0], [10.0, 10.0]),
            100,
            ColorBy::Color,
            colours,
        );
        let pixmap = painter.paint(&world);
        pixmap.pixels().iter().map(|p| p.blue() > 200).collect()
    }

    #[test]
    fn discs_reaching_into_the_view_are_drawn_and_the_rest_are_not() {
        // Centred outside the view, reaching 0.5 into it: its edge shows.
        let edge = painted(&[([-0.5, 5.0], 1.0)]);
        assert!(edge[50 * 100], "the disc's part inside the view is drawn");
        assert!(!edge[50 * 100 + 10]);
        // Far outside, huge or not: nothing.
        let outside = painted(&[([-50.0, 5.0], 1.0), ([5.0, 1e9], 3.0)]);
        assert!(outside.iter().all(|&blue| !blue));
        // Inside: drawn.
        let inside = painted(&[([5.0, 5.0], 1.0)]);
        assert!(inside[50 * 100 + 50]);
    }

    #[test]
    fn shapes_of_any_size_and_place_are_drawn_without_a_panic() {
        // A disc far larger than the picture, centred off it: its edge crosses the view.
        let huge = painted(&[([-1e9 + 5.0, 5.0], 1e9)]);
        assert!(
            huge[50 * 100 + 40] && !huge[50 * 100 + 60],
            "the edge at x = 5"
        );
        // Covering all of it.
        assert!(painted(&[([5.0, 5.0], 4.3e9)]).iter().all(|&blue| blue));
        let mut pixmap = Pixmap::new(100, 100).unwrap();
        let paint = Paint::default();
        for (x, y, r) in [(1e30, 5.0, 1e31), (-3e38, 3e38, 1e3), (50.0, 50.0, 3e38)] {
            fill_circle(&mut pixmap, x, y, r, &paint);
        }
        // Segments clipped near the picture, whatever their ends.
        assert_eq!(
            clip_segment((-1e20, 50.0), (-1e19, 50.0), (100.0, 100.0)),
            None
        );
        let [a, b] = clip_segment((-1e20, 50.0), (1e20, 50.0), (100.0, 100.0)).unwrap();
        let limit = RASTER_LIMIT as f32;
        assert_eq!((a, b), ((-limit, 50.0), (100.0 + limit, 50.0)));
        assert_eq!(
            clip_segment((10.0, 10.0), (20.0, 30.0), (100.0, 100.0)),
            Some([(10.0, 10.0), (20.0, 30.0)])
        );
    }
}

//! The simulation picture: discs rasterised on the CPU into an RGBA buffer that becomes one
//! texture per frame.
//!
//! Why not one egui shape per disc: 100,000 tessellated circles cost far more than a frame on
//! a software renderer (Mesa's llvmpipe). Filling each disc's pixels directly is linear in the
//! pixels covered, needs no GPU features, and runs the same in a browser.

use bounce::{ContactKind, Region, Shape, World};
use bounce_scenario::Rgb;
pub use bounce_scenario::palette::Palette;

/// Background of the picture.
pub const BACKGROUND: Rgb = [17, 20, 26];
const BOX_EDGE: Rgb = [90, 96, 110];
/// The marks where a Lees–Edwards box's sliding images stand.
const SLIDE_MARK: Rgb = [230, 170, 60];
/// Sensor outlines.
pub const SENSOR: Rgb = [110, 150, 230];
/// Impacts of the last step (contact events' begins).
pub const FLASH: Rgb = [255, 236, 120];

/// Which part of the world is shown: a centre and a scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// World point at the middle of the picture.
    pub centre: [f64; 2],
    /// Pixels per world unit.
    pub scale: f64,
}

impl View {
    /// A view showing `[min, max]` whole in a `width` × `height` picture, with a small margin.
    pub fn fit(min: [f64; 2], max: [f64; 2], width: usize, height: usize) -> Self {
        let w = (max[0] - min[0]).max(1e-9);
        let h = (max[1] - min[1]).max(1e-9);
        let scale = (width as f64 / w).min(height as f64 / h) * 0.96;
        View {
            centre: [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0],
            scale: if scale.is_finite() && scale > 0.0 {
                scale
            } else {
                1.0
            },
        }
    }

    /// World → picture pixels (y down).
    pub fn to_pixel(&self, p: [f64; 2], width: usize, height: usize) -> [f64; 2] {
        [
            (p[0] - self.centre[0]) * self.scale + width as f64 / 2.0,
            (self.centre[1] - p[1]) * self.scale + height as f64 / 2.0,
        ]
    }

    /// Picture pixels → world.
    pub fn to_world(&self, px: [f64; 2], width: usize, height: usize) -> [f64; 2] {
        [
            (px[0] - width as f64 / 2.0) / self.scale + self.centre[0],
            self.centre[1] - (px[1] - height as f64 / 2.0) / self.scale,
        ]
    }

    /// Zooms by `factor` keeping the world point under `px` in place.
    pub fn zoom_at(&mut self, px: [f64; 2], factor: f64, width: usize, height: usize) {
        let anchor = self.to_world(px, width, height);
        self.scale = (self.scale * factor).clamp(1e-6, 1e6);
        let moved = self.to_world(px, width, height);
        self.centre[0] += anchor[0] - moved[0];
        self.centre[1] += anchor[1] - moved[1];
    }
}

/// An RGBA picture of the world.
pub struct Raster {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// RGBA, row-major, top row first.
    pub pixels: Vec<u8>,
}

impl Raster {
    /// A picture of the given size.
    pub fn new(width: usize, height: usize) -> Self {
        Raster {
            width,
            height,
            pixels: vec![0; width * height * 4],
        }
    }

    fn put(&mut self, x: isize, y: isize, c: Rgb) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            let k = (y as usize * self.width + x as usize) * 4;
            self.pixels[k..k + 4].copy_from_slice(&[c[0], c[1], c[2], 255]);
        }
    }

    /// Draws the world as `view` sees it, the obstacles in `obstacle_colours` (one per
    /// obstacle, grey where missing).
    pub fn draw(
        &mut self,
        world: &World,
        view: &View,
        palette: &Palette,
        obstacle_colours: &[Rgb],
    ) {
        for px in self.pixels.chunks_exact_mut(4) {
            px.copy_from_slice(&[BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 255]);
        }
        let (w, h) = (self.width, self.height);
        if let Some((min, max)) = world.config().boundary.bounds() {
            let a = view.to_pixel([min[0], max[1]], w, h);
            let b = view.to_pixel([max[0], min[1]], w, h);
            let (x0, y0, x1, y1) = (a[0] as isize, a[1] as isize, b[0] as isize, b[1] as isize);
            for x in x0.max(0)..=x1.min(w as isize - 1) {
                self.put(x, y0, BOX_EDGE);
                self.put(x, y1, BOX_EDGE);
            }
            for y in y0.max(0)..=y1.min(h as isize - 1) {
                self.put(x0, y, BOX_EDGE);
                self.put(x1, y, BOX_EDGE);
            }
            if let Some(offset) = world.lees_edwards_offset() {
                // Where the sliding images' corners stand: the one above at `min + δ` on the
                // top edge, the one below at `min − δ` on the bottom edge (each wrapped).
                let width = max[0] - min[0];
                let tick = 0.03 * (max[1] - min[1]);
                for (edge, shift, inward) in [(max[1], offset, -tick), (min[1], -offset, tick)] {
                    let x = min[0] + (shift).rem_euclid(width);
                    let a = view.to_pixel([x, edge], w, h);
                    let b = view.to_pixel([x, edge + inward], w, h);
                    self.line(a, b, SLIDE_MARK);
                }
            }
        }
        // Emitter regions outlined in green, sinks in red.
        let config = world.config();
        let regions = config
            .emitters
            .iter()
            .map(|e| (e.min, e.max, [90, 170, 110]))
            .chain(config.sinks.iter().map(|s| (s.min, s.max, [190, 90, 90])));
        for (min, max, colour) in regions {
            let corners = [
                [min[0], min[1]],
                [max[0], min[1]],
                [max[0], max[1]],
                [min[0], max[1]],
            ]
            .map(|c| view.to_pixel(c, w, h));
            for k in 0..4 {
                self.line(corners[k], corners[(k + 1) % 4], colour);
            }
        }
        // Sensors outlined in blue.
        for sensor in &config.sensors {
            let outline: Vec<[f64; 2]> = match sensor.region {
                Region::Box { min, max } => {
                    vec![
                        [min[0], min[1]],
                        [max[0], min[1]],
                        [max[0], max[1]],
                        [min[0], max[1]],
                    ]
                }
                Region::Circle { centre, radius } => (0..48)
                    .map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / 48.0;
                        [centre[0] + radius * a.cos(), centre[1] + radius * a.sin()]
                    })
                    .collect(),
            };
            let pixels: Vec<[f64; 2]> = outline.iter().map(|&c| view.to_pixel(c, w, h)).collect();
            for k in 0..pixels.len() {
                self.line(pixels[k], pixels[(k + 1) % pixels.len()], SENSOR);
            }
        }
        for (k, shape) in world.obstacle_shapes().iter().enumerate() {
            let colour = obstacle_colours
                .get(k)
                .copied()
                .unwrap_or(bounce_scenario::OBSTACLE_GREY);
            match *shape {
                Shape::Segment { a, b } => {
                    let (a, b) = (view.to_pixel(a, w, h), view.to_pixel(b, w, h));
                    self.line(a, b, colour);
                }
                Shape::Peg { centre, radius } => {
                    let [cx, cy] = view.to_pixel(centre, w, h);
                    self.disc(cx, cy, (radius * view.scale).max(0.7), colour);
                }
            }
        }
        let p = world.particles();
        for i in 0..p.len() {
            let [cx, cy] = view.to_pixel([p.x()[i], p.y()[i]], w, h);
            let r = p.radius()[i] * view.scale;
            let colour = palette.colour(
                p.ids()[i].0 as usize,
                p.vx()[i].hypot(p.vy()[i]),
                p.radius()[i],
                p.angular_velocity().get(i).copied().unwrap_or(0.0),
            );
            self.disc(cx, cy, r, colour);
            if let Some(&theta) = p.orientation().get(i)
                && r >= 2.0
            {
                // Where the disc has turned: a radius in a darker shade.
                let tip = [cx + r * theta.cos(), cy - r * theta.sin()];
                self.line([cx, cy], tip, colour.map(|c| (c as f64 * 0.4) as u8));
            }
        }
        self.flash_impacts(world, view);
    }

    /// The contacts that began in the last step (with contact events on), a bright spot at
    /// each contact point, larger for a harder impact (the step's hardest: four pixels).
    fn flash_impacts(&mut self, world: &World, view: &View) {
        let begins = || (world.contact_events().iter()).filter(|e| e.kind == ContactKind::Begin);
        let hardest = begins().map(|e| e.normal_impulse).fold(0.0f64, f64::max);
        if hardest <= 0.0 {
            return;
        }
        let (w, h) = (self.width, self.height);
        for event in begins() {
            let [x, y] = view.to_pixel(event.point, w, h);
            let r = 1.5 + 2.5 * (event.normal_impulse / hardest).sqrt();
            self.disc(x, y, r, FLASH);
        }
    }

    /// A filled disc: the pixels whose centres lie inside it (one pixel when smaller).
    fn disc(&mut self, cx: f64, cy: f64, r: f64, colour: Rgb) {
        let (w, h) = (self.width, self.height);
        if cx + r < 0.0 || cy + r < 0.0 || cx - r > w as f64 || cy - r > h as f64 {
            return;
        }
        if r < 0.7 {
            self.put(cx as isize, cy as isize, colour);
            return;
        }
        let y_lo = (cy - r).floor().max(0.0) as usize;
        let y_hi = ((cy + r).ceil() as usize).min(h);
        for y in y_lo..y_hi {
            let dy = y as f64 + 0.5 - cy;
            let half = r * r - dy * dy;
            if half < 0.0 {
                continue;
            }
            let half = half.sqrt();
            let x_lo = (cx - half + 0.5).floor().max(0.0) as usize;
            let x_hi = ((cx + half + 0.5).floor().max(0.0) as usize).min(w);
            let row = y * w;
            for x in x_lo..x_hi {
                let k = (row + x) * 4;
                self.pixels[k..k + 4].copy_from_slice(&[colour[0], colour[1], colour[2], 255]);
            }
        }
    }

    /// A line two pixels wide from `a` to `b` (pixels), clipped to the picture.
    fn line(&mut self, a: [f64; 2], b: [f64; 2], colour: Rgb) {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        // One step per pixel along the longer axis, at most a few picture sizes.
        let limit = 4.0 * (self.width + self.height) as f64;
        let steps = dx.abs().max(dy.abs()).ceil().clamp(1.0, limit) as usize;
        let thick_x = dy.abs() > dx.abs();
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = ((a[0] + t * dx).floor(), (a[1] + t * dy).floor());
            if !(x.is_finite() && y.is_finite()) {
                return;
            }
            let (x, y) = (x as isize, y as isize);
            self.put(x, y, colour);
            if thick_x {
                self.put(x + 1, y, colour);
            } else {
                self.put(x, y + 1, colour);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bounce::{Boundary, Config, Particle};
    use bounce_scenario::ColorBy;

    #[test]
    fn view_round_trips_and_zooms_about_the_cursor() {
        let mut v = View::fit([0.0, 0.0], [100.0, 50.0], 400, 200);
        let px = v.to_pixel([30.0, 20.0], 400, 200);
        let back = v.to_world(px, 400, 200);
        assert!((back[0] - 30.0).abs() < 1e-9 && (back[1] - 20.0).abs() < 1e-9);
        v.zoom_at(px, 2.0, 400, 200);
        let again = v.to_pixel([30.0, 20.0], 400, 200);
        assert!((again[0] - px[0]).abs() < 1e-9 && (again[1] - px[1]).abs() < 1e-9);
    }

    #[test]
    fn discs_land_where_the_particles_are() {
        let mut world = World::new(Config {
            boundary: Boundary::walls([0.0, 0.0], [20.0, 10.0]),
            ..Config::default()
        })
        .unwrap();
        world
            .add_particle(Particle::new([5.0, 5.0], [0.0, 0.0], 1.0))
            .unwrap();
        let view = View {
            centre: [10.0, 5.0],
            scale: 10.0,
        };
        let palette = Palette {
            colour_by: ColorBy::Color,
            colours: vec![Some([255, 0, 0])],
            speed_scale: 1.0,
            radius_range: [1.0, 1.0],
            spin_scale: 1.0,
        };
        let mut raster = Raster::new(200, 100);
        raster.draw(&world, &view, &palette, &[]);
        let at = |x: usize, y: usize| &raster.pixels[(y * 200 + x) * 4..(y * 200 + x) * 4 + 3];
        assert_eq!(at(50, 50), &[255, 0, 0]);
        assert_eq!(at(58, 50), &[255, 0, 0]);
        assert_eq!(at(62, 50), &BACKGROUND);
        assert_eq!(at(150, 20), &BACKGROUND);
    }

    /// Colour by speed, nothing else set.
    fn by_speed() -> Palette {
        Palette {
            colour_by: ColorBy::Speed,
            colours: Vec::new(),
            speed_scale: 1.0,
            radius_range: [1.0, 1.0],
            spin_scale: 1.0,
        }
    }

    #[test]
    fn emitter_and_sink_regions_are_outlined() {
        let world = World::new(Config {
            boundary: Boundary::walls([0.0, 0.0], [20.0, 10.0]),
            emitters: vec![bounce::Emitter::new([2.0, 2.0], [6.0, 8.0], 0.3)],
            sinks: vec![bounce::Sink {
                min: [14.0, 2.0],
                max: [18.0, 8.0],
            }],
            ..Config::default()
        })
        .unwrap();
        let view = View {
            centre: [10.0, 5.0],
            scale: 10.0,
        };
        let palette = by_speed();
        let mut raster = Raster::new(200, 100);
        raster.draw(&world, &view, &palette, &[]);
        let at = |p: [f64; 2]| {
            let [x, y] = view.to_pixel(p, 200, 100);
            let k = (y as usize * 200 + x as usize) * 4;
            [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
        };
        assert_eq!(at([2.0, 5.0]), [90, 170, 110], "the emitter's left edge");
        assert_eq!(at([16.0, 2.0]), [190, 90, 90], "the sink's bottom edge");
        assert_eq!(at([16.0, 5.0]), BACKGROUND, "inside the sink");
    }

    #[test]
    fn a_sheared_box_marks_where_its_sliding_copies_stand() {
        // 20 × 10 at shear rate 0.2: the copy above moves at 2; after 1.5 it stands 3 along.
        let mut world = World::new(Config {
            boundary: Boundary::lees_edwards([0.0, 0.0], [20.0, 10.0], 0.2),
            ..Config::default()
        })
        .unwrap();
        world.step(1.5).unwrap();
        let view = View {
            centre: [10.0, 5.0],
            scale: 10.0,
        };
        let mut raster = Raster::new(200, 100);
        raster.draw(&world, &view, &by_speed(), &[]);
        let at = |p: [f64; 2]| {
            let [x, y] = view.to_pixel(p, 200, 100);
            let k = (y as usize * 200 + x as usize) * 4;
            [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
        };
        // Just inside the top edge at x = 3, and the bottom edge at x = −3 → 17.
        assert_eq!(at([3.0, 9.85]), SLIDE_MARK, "the copy above");
        assert_eq!(at([17.0, 0.15]), SLIDE_MARK, "the copy below");
        assert_eq!(at([8.0, 9.85]), BACKGROUND, "nothing elsewhere");
    }

    #[test]
    fn sensors_are_outlined_and_impacts_flash() {
        let mut world = World::new(Config {
            boundary: Boundary::walls([0.0, 0.0], [20.0, 10.0]),
            contact_events: true,
            sensors: vec![bounce::Sensor::new(
                "gate",
                Region::Box {
                    min: [15.0, 2.0],
                    max: [18.0, 8.0],
                },
            )],
            ..Config::default()
        })
        .unwrap();
        // Two discs meet head on at x = 10 in the step after 10.
        world
            .add_particle(Particle::new([5.0, 5.0], [1.0, 0.0], 2.0))
            .unwrap();
        world
            .add_particle(Particle::new([15.0, 5.0], [-1.0, 0.0], 2.0))
            .unwrap();
        let view = View {
            centre: [10.0, 5.0],
            scale: 10.0,
        };
        let palette = by_speed();
        let mut raster = Raster::new(200, 100);
        let at = |raster: &Raster, p: [f64; 2]| {
            let [x, y] = view.to_pixel(p, 200, 100);
            let k = (y as usize * 200 + x as usize) * 4;
            [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
        };
        let mut flashed = false;
        for _ in 0..80 {
            world.step(0.1).unwrap();
            raster.draw(&world, &view, &palette, &[]);
            let contact = !world.contact_events().is_empty();
            flashed |= contact && at(&raster, [10.0, 5.0]) == FLASH;
            if !contact {
                assert_ne!(
                    at(&raster, [10.0, 5.0]),
                    FLASH,
                    "no flash without a contact"
                );
            }
        }
        assert!(flashed, "the impact flashed where the discs touched");
        assert_eq!(at(&raster, [16.5, 2.0]), SENSOR, "the sensor's bottom edge");
    }
}

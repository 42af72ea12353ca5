//! Frames read right: the time written in the top-left corner, a key to the colouring in the
//! top-right (the speed ramp's ends, or the scenario's named colours), and walls that stand
//! out from the background.

mod common;

use common::{Scratch, bounce, output};

/// The frame of `text`'s run at step `step`, as RGB rows.
fn frame(text: &str, step: u64) -> tiny_skia::Pixmap {
    let s = Scratch::new();
    let scenario = s.scenario("f.toml", text);
    let (code, _, err) = output(
        bounce()
            .arg("run")
            .arg(&scenario)
            .arg("--out")
            .arg(s.path("out"))
            .arg("-q"),
    );
    assert_eq!(code, 0, "{err}");
    tiny_skia::Pixmap::load_png(s.path(&format!("out/frames/frame_{step:07}.png"))).unwrap()
}

fn rgb(png: &tiny_skia::Pixmap, x: u32, y: u32) -> [u8; 3] {
    let p = png.pixel(x, y).unwrap();
    [p.red(), p.green(), p.blue()]
}

/// Whether some pixel in the rectangle is within 30 of `colour` in every channel.
fn shows(png: &tiny_skia::Pixmap, (x0, y0, x1, y1): (u32, u32, u32, u32), colour: [u8; 3]) -> bool {
    (y0..y1).any(|y| {
        (x0..x1).any(|x| {
            rgb(png, x, y)
                .iter()
                .zip(colour)
                .all(|(a, b)| a.abs_diff(b) <= 30)
        })
    })
}

const GAS: &str = "[world]\nmin = [0.0, 0.0]\nmax = [40.0, 20.0]\n[time]\ndt = 0.01\nsteps = 10\n\
                   [[gas]]\ncount = 50\nradius = 0.3\nspeed = 1.0\nregion = { min = [0.0, 0.0], max = [40.0, 12.0] }\n\
                   [output]\nframe_every = 10\nframe_width = 800\n";

#[test]
fn a_frame_says_its_time_and_keys_its_speed_colours() {
    let png = frame(GAS, 10);
    let (w, h) = (png.width(), png.height());
    assert_eq!((w, h), (800, 400));
    // Light text top left ("t = 0.1"), on the dark background.
    assert!(
        shows(&png, (0, 0, 120, 30), [235, 238, 245]),
        "no time written"
    );
    // The speed ramp's two ends top right: dark blue and yellow.
    assert!(
        shows(&png, (w - 300, 0, w, 30), [59, 76, 192]),
        "no slow end of the key"
    );
    assert!(
        shows(&png, (w - 300, 0, w, 30), [250, 230, 40]),
        "no fast end of the key"
    );
    // The walls: the box's left edge, halfway up, is light.
    let wall = rgb(&png, 1, h / 2);
    assert!(wall.iter().all(|&c| c > 150), "the wall is {wall:?}");
}

#[test]
fn a_frame_coloured_by_the_scenario_names_its_colours() {
    let text = GAS.replace(
        "speed = 1.0\n",
        "speed = 1.0\ncolor = \"red\"\ntype = \"hot\"\n",
    ) + "color_by = \"color\"\n";
    let png = frame(&text, 10);
    let w = png.width();
    // A red swatch in the key, top right, beside its name.
    assert!(shows(&png, (w - 200, 0, w, 30), [220, 50, 47]), "no swatch");
    assert!(shows(&png, (w - 200, 0, w, 30), [235, 238, 245]), "no name");
    // And no speed ramp.
    assert!(!shows(&png, (w - 300, 0, w, 30), [250, 230, 40]));
}

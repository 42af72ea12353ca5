//! The viewer's behaviour, driven without a window.

use bounce::{Obstacle, RestingContacts};

use super::panels::structure_of;
use super::*;

fn app(name: &str) -> ViewerApp {
    let text = bounce_scenario::template(name).unwrap();
    ViewerApp::new(Some((name.into(), text.into())), None).unwrap()
}

fn step_of(status: &str) -> u64 {
    status.split_whitespace().nth(1).unwrap().parse().unwrap()
}

#[test]
fn run_to_pauses_and_reaches_the_step_with_native_bits() {
    let mut a = app("gas");
    a.run_to(25);
    assert!(!a.running);
    let status = a.status();
    assert_eq!(step_of(&status), 25);
    // The same scenario stepped directly gives the same hash.
    let text = bounce_scenario::template("gas").unwrap();
    let scenario = bounce_scenario::parse(text, "gas").unwrap();
    let mut world = scenario.build(text, "gas").unwrap().world;
    for _ in 0..25 {
        world.step(scenario.time.dt).unwrap();
    }
    assert!(
        status.contains(&format!("{:016x}", world.state_hash())),
        "{status}"
    );
}

#[test]
fn checkpoints_save_and_load_through_the_path_field() {
    let dir = std::env::temp_dir().join(format!("bounce-viewer-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("c.bin");
    let mut a = app("mixing");
    a.run_to(10);
    a.path = file.display().to_string();
    a.save_checkpoint();
    assert!(a.message.starts_with("saved"), "{}", a.message);
    let saved = a.status();
    a.run_to(20);
    a.load_checkpoint();
    assert!(a.message.starts_with("loaded"), "{}", a.message);
    assert_eq!(
        a.status().replace("running false", ""),
        saved.replace("running false", "")
    );
    a.path = dir.join("missing.bin").display().to_string();
    a.load_checkpoint();
    assert!(a.message.contains("cannot read"), "{}", a.message);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn opening_and_resetting_scenarios() {
    let mut a = app("gas");
    a.run_to(5);
    assert!(a.open_text("bad.toml", "[world]\n").is_err());
    assert_eq!(step_of(&a.status()), 5, "a bad file leaves the world alone");
    a.open_builtin("newtons-cradle").unwrap();
    assert!(a.status().contains("particles 6"), "{}", a.status());
    assert!(a.open_builtin("nope").is_err());
    a.run_to(3);
    a.reset();
    assert_eq!(step_of(&a.status()), 0);
}

#[test]
fn the_structure_panel_reads_a_crystal_and_a_fluid() {
    // The hard-discs template starts on a triangular lattice and melts.
    let mut a = app("hard-discs");
    let (crystal, profile) = structure_of(&a.session.world);
    assert!(crystal > 0.9, "{crystal}");
    let profile = profile.unwrap();
    assert_eq!(profile.count.iter().sum::<u64>(), 2000);
    a.run_to(100);
    let (fluid, _) = structure_of(&a.session.world);
    assert!(fluid < 0.2, "{fluid}");
    // The panel draws with it on.
    a.show_structure = true;
    let ctx = egui::Context::default();
    let output = ctx.run_ui(egui::RawInput::default(), |ui| a.panels(ui));
    output.drop_without_applying_deltas();
    // An open world has no profiles.
    let mut open = bounce::World::new(bounce::Config::default()).unwrap();
    for x in [0.0, 3.0] {
        open.add_particle(bounce::Particle::new([x, 0.0], [0.0, 0.0], 1.0))
            .unwrap();
    }
    assert!(structure_of(&open).1.is_none());
}

#[test]
fn drawing_the_controls_leaves_a_scenarios_values_alone() {
    // The hard-discs template observes every 0.1, beyond the dt slider's 0.05.
    let mut a = app("hard-discs");
    let (dt, config) = (a.session.dt, a.session.world.config().clone());
    let ctx = egui::Context::default();
    for _ in 0..2 {
        let output = ctx.run_ui(egui::RawInput::default(), |ui| a.controls(ui));
        output.drop_without_applying_deltas();
    }
    assert_eq!(a.session.dt, 0.1);
    assert_eq!((a.session.dt, a.session.world.config()), (dt, &config));
}

#[test]
fn the_method_switch_restarts_the_gas_event_driven_and_back() {
    let mut a = app("gas");
    a.run_to(5);
    a.switch_method(Method::EventDriven);
    assert_eq!(a.session.world.config().method, Method::EventDriven);
    assert_eq!(step_of(&a.status()), 0, "{}", a.message);
    let count = a.session.world.len();
    a.run_to(30);
    assert!(a.session.world.stats().collisions > 0, "{}", a.message);
    assert_eq!(a.session.world.len(), count);
    a.switch_method(Method::TimeStepped);
    assert_eq!(a.session.world.config().method, Method::TimeStepped);
    // A scene the method cannot run says why and keeps the world it had.
    a.open_builtin("pile").unwrap();
    a.switch_method(Method::EventDriven);
    assert!(a.message.contains("method"), "{}", a.message);
    assert_eq!(a.session.world.config().method, Method::TimeStepped);
}

#[test]
fn a_scenario_with_resting_contacts_opens_with_them() {
    let text = bounce_scenario::template("pile")
        .unwrap()
        .replace("[time]", "resting_contacts = \"rest\"\n\n[time]");
    let mut a = app("gas");
    assert_eq!(
        a.session.world.config().resting_contacts,
        RestingContacts::Bounce
    );
    a.open_text("pile.toml", &text).unwrap();
    assert_eq!(
        a.session.world.config().resting_contacts,
        RestingContacts::Rest
    );
}

#[test]
fn rough_discs_show_where_they_turned_and_colour_by_spin() {
    // One large disc turned a quarter turn, spinning counter-clockwise, friction on.
    let text = "[world]\nboundary = \"walls\"\nmin = [0.0, 0.0]\nmax = [40.0, 40.0]\n\
                friction = 0.5\n[time]\ndt = 0.01\nsteps = 10\n\
                [[disc]]\nposition = [20.0, 20.0]\nradius = 8.0\nangular_velocity = 1.0\n";
    let mut a = app("gas");
    a.open_text("spin.toml", text).unwrap();
    assert_eq!(a.session.world.config().friction, 0.5);
    // π/2 at ω = 1: the radius points up.
    a.session
        .world
        .set_angular_velocities(&[std::f64::consts::FRAC_PI_2 / 0.1])
        .unwrap();
    a.run_to(10);
    a.session.world.set_angular_velocities(&[1.0]).unwrap();
    a.colour_by = ColorBy::Spin;
    a.palette = Palette::for_world(&a.session.world, ColorBy::Spin, a.session.colours.clone());
    let view = View::fit([0.0, 0.0], [40.0, 40.0], 200, 200);
    let mut raster = Raster::new(200, 200);
    raster.draw(&a.session.world, &view, &a.palette, &a.obstacle_colours);
    let pixel = |p: [f64; 2]| {
        let [x, y] = view.to_pixel(p, 200, 200);
        let k = (y as usize * 200 + x as usize) * 4;
        [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
    };
    let theta = a.session.world.orientations()[0];
    assert!(
        (theta - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "{theta}"
    );
    // Counter-clockwise at the palette's scale (2.5 × its own): red of the spin ramp.
    let colour = bounce_scenario::spin_ramp(1.0 / 2.5);
    assert_eq!(pixel([20.0, 14.0]), colour, "the disc below its centre");
    let shade = colour.map(|c| (c as f64 * 0.4) as u8);
    let on_radius = (-2..=2).any(|d| pixel([20.0 + d as f64 * 0.1, 25.0]) == shade);
    assert!(on_radius, "the radius line upwards");
}

#[test]
fn spawning_adds_coloured_discs_and_refuses_bad_places() {
    let mut a = app("newtons-cradle");
    let n = a.session.world.len();
    a.spawn([20.0, 3.0], [1.0, 0.0]);
    assert_eq!(a.session.world.len(), n + 1);
    assert_eq!(a.session.colours.len(), n + 1);
    a.spawn([500.0, 3.0], [0.0, 0.0]);
    assert_eq!(a.session.world.len(), n + 1, "outside the walls");
    assert!(a.message.contains("cannot place"), "{}", a.message);
}

#[test]
fn drawn_obstacles_join_the_world_and_the_picture() {
    // A wall across the gas box and a peg: both in the world, drawn in grey, and a
    // scenario's own obstacles keep their colours.
    let mut a = app("gas");
    a.add_obstacle(Obstacle::segment([10.0, 45.0], [80.0, 45.0]));
    a.add_obstacle(Obstacle::peg([45.0, 20.0], 2.0));
    a.add_obstacle(Obstacle::peg([45.0, 20.0], -1.0));
    assert_eq!(a.obstacle_count(), 2);
    assert!(a.message.contains("cannot add"), "{}", a.message);
    // One step pushes the discs off them.
    a.run_to(1);
    let view = View::fit([0.0, 0.0], [90.0, 90.0], 300, 300);
    let mut raster = Raster::new(300, 300);
    raster.draw(&a.session.world, &view, &a.palette, &a.obstacle_colours);
    let grey = bounce_scenario::OBSTACLE_GREY;
    let pixel = |p: [f64; 2]| {
        let [x, y] = view.to_pixel(p, 300, 300);
        let k = (y as usize * 300 + x as usize) * 4;
        [raster.pixels[k], raster.pixels[k + 1], raster.pixels[k + 2]]
    };
    assert_eq!(pixel([45.0, 20.0]), grey, "the peg");
    let on_wall = (-1..=1).any(|d| pixel([30.0, 45.0 + d as f64 * 0.2]) == grey);
    assert!(on_wall, "the wall");
    let galton = app("galton-board");
    assert_eq!(galton.obstacle_colours[0], [0x8d, 0xa9, 0xc4]);
}

#[test]
fn emitted_discs_appear_in_their_emitters_colour() {
    let text = r##"
[world]
min = [0.0, 0.0]
max = [20.0, 20.0]
[time]
dt = 0.05
steps = 100
[[emitter]]
region = { min = [2.0, 2.0], max = [18.0, 18.0] }
rate = 20.0
radius = 0.3
color = "#00ff00"
[[sink]]
region = { min = [0.0, 0.0], max = [20.0, 1.0] }
"##;
    let mut a = app("gas");
    a.open_text("emit.toml", text).unwrap();
    for _ in 0..10 {
        a.step();
    }
    assert_eq!(a.session.world.len(), 10, "{}", a.status());
    let last = a.session.world.next_id() as usize - 1;
    assert_eq!(a.palette.colours[last], Some([0, 255, 0]));
    // A checkpoint loaded into the freshly opened scenario (through the session, as the
    // CLI resumes) gives the emitted discs their colour again.
    let dir = std::env::temp_dir().join(format!("bounce-viewer-emit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    a.path = dir.join("c.bin").display().to_string();
    a.save_checkpoint();
    let saved = a.status();
    a.open_text("emit.toml", text).unwrap();
    assert_eq!(a.session.world.len(), 0);
    a.path = dir.join("c.bin").display().to_string();
    a.load_checkpoint();
    assert!(a.message.starts_with("loaded"), "{}", a.message);
    assert_eq!(a.status(), saved);
    assert_eq!(a.palette.colours[last], Some([0, 255, 0]));
    std::fs::remove_dir_all(&dir).unwrap();
}

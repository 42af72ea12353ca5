//! The engines under test, each set up for the closest physics to bounce's: discs with the
//! scene's friction (zero but in `pile-settled-friction`) and restitution, sleeping off,
//! restitution threshold 0, fixed walls.

use std::time::Instant;

use anyhow::{Result, anyhow, bail};

use crate::scenes::Setup;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Engine {
    Bounce1,
    Bounce2,
    Rapier1,
    Rapier2,
    Box2d1,
    Box2d2,
}

impl Engine {
    pub const ALL: [Engine; 6] = [
        Engine::Bounce1,
        Engine::Bounce2,
        Engine::Rapier1,
        Engine::Rapier2,
        Engine::Box2d1,
        Engine::Box2d2,
    ];

    pub fn name(&self) -> &'static str {
        match self {
            Engine::Bounce1 => "bounce (1 thread)",
            Engine::Bounce2 => "bounce (2 threads)",
            Engine::Rapier1 => "rapier2d 0.36 (1 thread)",
            Engine::Rapier2 => "rapier2d 0.36 (2 threads)",
            Engine::Box2d1 => "Box2D v3 / boxdd 0.6 (1 worker)",
            Engine::Box2d2 => "Box2D v3 / boxdd 0.6 (2 workers)",
        }
    }

    /// Whether this is bounce (the peers are skipped where they cannot run).
    pub fn is_bounce(&self) -> bool {
        matches!(self, Engine::Bounce1 | Engine::Bounce2)
    }

    pub fn parse(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|e| e.name() == name)
            .ok_or_else(|| anyhow!("unknown engine {name:?}"))
    }

    /// The engine's simulation of `setup`, which it consumes (so the shared copy is freed
    /// and the peak memory measured is the engine's).
    pub fn create(&self, setup: Setup) -> Result<Box<dyn Sim>> {
        Ok(match self {
            Engine::Bounce1 => Box::new(BounceSim::new(setup, 1)?),
            Engine::Bounce2 => Box::new(BounceSim::new(setup, 2)?),
            Engine::Rapier1 => Box::new(RapierSim::new(&setup, 1)?),
            Engine::Rapier2 => Box::new(RapierSim::new(&setup, 2)?),
            Engine::Box2d1 => Box::new(Box2dSim::new(&setup, 1)?),
            Engine::Box2d2 => Box::new(Box2dSim::new(&setup, 2)?),
        })
    }
}

/// A steppable simulation.
pub trait Sim {
    /// One step of `dt`; returns wall seconds.
    fn step_timed(&mut self) -> f64;
    /// What differs from bounce's physics.
    fn note(&self) -> String;
    /// Seconds in each stage of the last step (integrate, bin, pairs, resolve, measure),
    /// the substeps that rebuilt the candidate list and the contacts resolved: bounce only.
    fn stages(&self) -> Option<([f64; 5], usize, usize)> {
        None
    }
}

fn timed(f: impl FnOnce()) -> f64 {
    let t = Instant::now();
    f();
    t.elapsed().as_secs_f64()
}

struct BounceSim {
    world: bounce::World,
    dt: f64,
}

impl BounceSim {
    fn new(mut setup: Setup, threads: usize) -> Result<Self> {
        let config = bounce::Config {
            boundary: bounce::Boundary::walls(setup.min, setup.max),
            gravity: setup.gravity,
            coefficient_of_restitution: setup.restitution,
            substeps: setup.substeps,
            obstacles: std::mem::take(&mut setup.obstacles),
            friction: setup.friction,
            ..bounce::Config::default()
        };
        let mut world = bounce::World::new(config)?;
        // Move the discs over in chunks from the back of the reversed list, giving the
        // list's memory back as it goes: both full copies never coexist.
        let discs = &mut setup.discs;
        discs.reverse();
        let mut added = 0;
        while !discs.is_empty() {
            let start = discs.len().saturating_sub(1 << 16);
            world
                .add_particles(discs[start..].iter().rev().copied())
                .map_err(|(i, e)| anyhow!("disc {}: {e}", added + i))?;
            added += discs.len() - start;
            discs.truncate(start);
            discs.shrink_to_fit();
        }
        world.set_threads(threads)?;
        Ok(BounceSim {
            world,
            dt: setup.dt,
        })
    }
}

impl Sim for BounceSim {
    fn step_timed(&mut self) -> f64 {
        let dt = self.dt;
        timed(|| {
            self.world.step(dt).expect("valid dt");
        })
    }

    fn note(&self) -> String {
        if self.world.config().is_rough() {
            "seed model with rough discs (friction 0.5), f64".into()
        } else {
            "seed model, f64".into()
        }
    }

    fn stages(&self) -> Option<([f64; 5], usize, usize)> {
        let p = self.world.profile();
        Some((
            [p.integrate, p.bin, p.pairs, p.resolve, p.measure],
            p.rebuilds,
            self.world.stats().pairs,
        ))
    }
}

struct RapierSim {
    world: rapier2d::prelude::PhysicsWorld,
    /// Rapier's `parallel` feature runs on the current rayon pool: this one sets the threads.
    pool: rayon::ThreadPool,
}

impl RapierSim {
    fn new(setup: &Setup, threads: usize) -> Result<Self> {
        use rapier2d::prelude::*;
        let mut world = PhysicsWorld {
            gravity: Vector::new(setup.gravity[0] as f32, setup.gravity[1] as f32),
            ..PhysicsWorld::default()
        };
        world.integration_parameters.dt = setup.dt as f32;
        world.integration_parameters.num_solver_iterations = setup.substeps as usize;
        let (e, mu) = (setup.restitution as f32, setup.friction as f32);
        for d in &setup.discs {
            let body = RigidBodyBuilder::dynamic()
                .translation(Vector::new(d.position[0] as f32, d.position[1] as f32))
                .linvel(Vector::new(d.velocity[0] as f32, d.velocity[1] as f32))
                .can_sleep(false)
                .build();
            let handle = world.bodies.insert(body);
            let collider = ColliderBuilder::ball(d.radius as f32)
                .friction(mu)
                .restitution(e)
                .restitution_combine_rule(CoefficientCombineRule::Max)
                .friction_combine_rule(CoefficientCombineRule::Min)
                .build();
            world
                .colliders
                .insert_with_parent(collider, handle, &mut world.bodies);
        }
        // Four walls as thick fixed boxes.
        let [x0, y0] = setup.min.map(|v| v as f32);
        let [x1, y1] = setup.max.map(|v| v as f32);
        let t = 5.0f32;
        let (w, h) = (x1 - x0, y1 - y0);
        for (cx, cy, hx, hy) in [
            (x0 - t, (y0 + y1) / 2.0, t, h / 2.0 + 2.0 * t),
            (x1 + t, (y0 + y1) / 2.0, t, h / 2.0 + 2.0 * t),
            ((x0 + x1) / 2.0, y0 - t, w / 2.0 + 2.0 * t, t),
            ((x0 + x1) / 2.0, y1 + t, w / 2.0 + 2.0 * t, t),
        ] {
            let wall = ColliderBuilder::cuboid(hx, hy)
                .translation(Vector::new(cx, cy))
                .friction(mu)
                .restitution(e)
                .build();
            world.colliders.insert(wall);
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        Ok(RapierSim { world, pool })
    }
}

impl Sim for RapierSim {
    fn step_timed(&mut self) -> f64 {
        let (world, pool) = (&mut self.world, &self.pool);
        timed(|| pool.install(|| world.step()))
    }

    fn note(&self) -> String {
        "f32, soft contacts, solver substeps = scene substeps".into()
    }
}

struct Box2dSim {
    world: boxdd::World,
    dt: f32,
    substeps: i32,
}

impl Box2dSim {
    fn new(setup: &Setup, workers: usize) -> Result<Self> {
        use boxdd::{
            BodyBuilder, BodyType, Foundation, Position, ShapeDef, SurfaceMaterial, Vec2,
            WorkerCount, WorldBuilder, shapes,
        };
        let foundation = Foundation::initialize_default().map_err(|e| anyhow!("{e:?}"))?;
        let def = WorldBuilder::from(foundation.world_def())
            .gravity(Vec2::new(setup.gravity[0] as f32, setup.gravity[1] as f32))
            .enable_sleep(false)
            .restitution_threshold(0.0)
            .worker_count(WorkerCount::new(workers as u32).map_err(|e| anyhow!("{e:?}"))?)
            .build()
            .map_err(|e| anyhow!("{e:?}"))?;
        let mut world = foundation.create_world(def).map_err(|e| anyhow!("{e:?}"))?;
        let material = SurfaceMaterial::new()
            .with_friction(setup.friction as f32)
            .and_then(|m| m.with_restitution(setup.restitution as f32))
            .map_err(|e| anyhow!("{e:?}"))?;
        let shape = ShapeDef::builder()
            .material(material)
            .density(1.0)
            .build()
            .map_err(|e| anyhow!("{e:?}"))?;
        for d in &setup.discs {
            let body = BodyBuilder::from(foundation.body_def())
                .body_type(BodyType::Dynamic)
                .position(Position::new(d.position[0] as f32, d.position[1] as f32))
                .linear_velocity(Vec2::new(d.velocity[0] as f32, d.velocity[1] as f32))
                .enable_sleep(false)
                .build()
                .map_err(|e| anyhow!("{e:?}"))?;
            let id = world.create_body(body).map_err(|e| anyhow!("{e:?}"))?;
            let circle = shapes::circle(Vec2::new(0.0, 0.0), d.radius as f32)
                .map_err(|e| anyhow!("{e:?}"))?;
            world
                .body(id)
                .map_err(|e| anyhow!("{e:?}"))?
                .create_circle(&shape, &circle)
                .map_err(|e| anyhow!("{e:?}"))?;
        }
        let ground = BodyBuilder::from(foundation.body_def())
            .body_type(BodyType::Static)
            .build()
            .map_err(|e| anyhow!("{e:?}"))?;
        let ground = world.create_body(ground).map_err(|e| anyhow!("{e:?}"))?;
        let [x0, y0] = setup.min.map(|v| v as f32);
        let [x1, y1] = setup.max.map(|v| v as f32);
        let corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            world
                .body(ground)
                .map_err(|e| anyhow!("{e:?}"))?
                .create_segment_between(&shape, Vec2::new(a.0, a.1), Vec2::new(b.0, b.1))
                .map_err(|e| anyhow!("{e:?}"))?;
        }
        if setup.substeps < 1 {
            bail!("substeps must be >= 1");
        }
        Ok(Box2dSim {
            world,
            dt: setup.dt as f32,
            substeps: setup.substeps as i32,
        })
    }
}

impl Sim for Box2dSim {
    fn step_timed(&mut self) -> f64 {
        let (dt, sub) = (self.dt, self.substeps);
        timed(|| {
            drop(self.world.step(dt, sub).expect("step"));
        })
    }

    fn note(&self) -> String {
        "f32, soft-step solver, native substeps".into()
    }
}

//! A scenario turned into a world: its discs placed table by table, the invalid ones and the
//! overlapping ones reported with their tables' lines.

use std::path::Path;

use bounce::law::Law;
use bounce::scene::{self, Gas, Lattice, Speeds};
use bounce::{Config, Particle, World};

use crate::lines::{LineIndex, line_of_key};
use crate::schema::{FileDiscs, FileSpec, Placement, Scenario, block_counts, block_spacing};
#[cfg(not(target_arch = "wasm32"))]
use crate::start;
use crate::{Limits, Problem, Rgb, ScenarioError, diagnose, parse_colour};

/// A scenario turned into a world.
pub struct Built {
    /// The world, particles added.
    pub world: World,
    /// Colour of each particle, indexed by id; `None` where the scenario sets none.
    pub colours: Vec<Option<Rgb>>,
    /// The particle types, in order of first appearance.
    pub types: Vec<String>,
    /// Each particle's index into `types`, by id.
    pub typeid: Vec<u32>,
    /// Each emitter's colour and index into `types`, for the discs it adds.
    pub emitted: Vec<(Option<Rgb>, u32)>,
}

/// Reads scenario text and places its discs, listing every problem of both: where the reading
/// found problems, the tables they are on are left out of the placement, so that the other
/// tables' problems (a disc outside the box, overlapping tables) are listed beside them.
pub(crate) fn read_and_build(
    source: &str,
    file: &str,
    limits: &Limits,
    dir: Option<&Path>,
) -> Result<(Scenario, Built), ScenarioError> {
    let examined = diagnose::examine(source);
    let fail = |problems| ScenarioError {
        file: file.to_string(),
        problems,
    };
    let Some(mut scenario) = examined.scenario else {
        return Err(fail(examined.problems));
    };
    scenario.dir = dir.map(Path::to_path_buf);
    if examined.problems.is_empty() {
        let built = scenario.build_with(source, file, limits)?;
        let problems = start_problems(&scenario, &built.world, source);
        if !problems.is_empty() {
            return Err(fail(problems));
        }
        return Ok((scenario, built));
    }
    let skip: Vec<usize> = examined.problems.iter().filter_map(|p| p.line).collect();
    let mut problems = examined.problems;
    if let Err(e) = scenario.build_skipping(source, file, limits, Some(&skip)) {
        problems.extend(e.problems);
        diagnose::sort(&mut problems);
    }
    Err(fail(problems))
}

/// Gives every disc of a table the table's tag.
fn tag(discs: &mut [Particle], tag: u64) {
    for disc in discs {
        disc.tag = tag;
    }
}

impl Scenario {
    /// The discs of a `[[file]]` table, placed in the world's box.
    #[cfg(not(target_arch = "wasm32"))]
    fn read_file(&self, spec: &FileSpec, config: &bounce::Config) -> Result<FileDiscs, String> {
        start::read_for(&self.file_path(spec), spec.frame, &config.boundary)
    }

    #[cfg(target_arch = "wasm32")]
    fn read_file(&self, spec: &FileSpec, _: &bounce::Config) -> Result<FileDiscs, String> {
        Err(format!(
            "{}: the web page cannot read files; paste the discs as [[disc]] tables",
            spec.path
        ))
    }

    /// Places the particles and returns the world, within the default [`Limits`]. `file` and
    /// `source` name problems.
    pub fn build(&self, source: &str, file: &str) -> Result<Built, ScenarioError> {
        self.build_with(source, file, &Limits::default())
    }

    /// Places the particles and returns the world; refuses up front, with the estimate, a
    /// scenario that needs more than `limits` allow.
    pub fn build_with(
        &self,
        source: &str,
        file: &str,
        limits: &Limits,
    ) -> Result<Built, ScenarioError> {
        self.build_skipping(source, file, limits, None)
    }

    /// [`Scenario::build_with`], listing every problem of the placement rather than the
    /// first: each table a generator cannot place, each invalid disc (the first few of a
    /// table), each pair of overlapping tables. With `skip` (the lines of problems a reading
    /// already reported) the particle tables starting on those lines are left out, and a
    /// configuration the world refuses (reported too) is replaced by its sound part, so the
    /// other tables are still checked.
    fn build_skipping(
        &self,
        source: &str,
        file: &str,
        limits: &Limits,
        skip: Option<&[usize]>,
    ) -> Result<Built, ScenarioError> {
        let checking = skip.is_some();
        let skip = skip.unwrap_or_default();
        let fail = |line: Option<usize>, message: String| ScenarioError {
            file: file.to_string(),
            problems: vec![Problem { line, message }],
        };
        let mut problems: Vec<Problem> = Vec::new();
        let lines = LineIndex::new(source);
        let estimate = self
            .estimate()
            .ok_or_else(|| fail(None, "the particle count overflows".into()))?;
        limits.check(&estimate).map_err(|m| fail(None, m))?;
        let mut world = match World::new(self.config()) {
            Ok(world) => world,
            Err(_) if checking => {
                World::new(placement_config(&self.config())).map_err(|_| ScenarioError {
                    file: file.to_string(),
                    problems: Vec::new(),
                })?
            }
            Err(e) => return Err(fail(None, e.to_string())),
        };
        let config = world.config().clone();
        let mut colours = Vec::new();
        // Every disc so far, so later generators keep clear of earlier tables' discs.
        let mut placed: Vec<Particle> = Vec::new();
        // Which table made which ids: (first id, what, line).
        let mut tables: Vec<(usize, String, usize)> = Vec::new();
        let mut types: Vec<String> = Vec::new();
        let mut typeid: Vec<u32> = Vec::new();
        // `own_types`: a file's own type for each disc (names and each disc's index).
        let mut add = |discs: Vec<Particle>,
                       (colour, kind): (&Option<String>, &Option<String>),
                       line: usize,
                       what: String,
                       placed: &mut Vec<Particle>,
                       own_types: Option<(&[String], &[u32])>| {
            let rgb = colour
                .as_deref()
                .map(|c| parse_colour(c).expect("checked in problems"));
            let n = discs.len();
            let mut type_of = |name: String| match types.iter().position(|t| *t == name) {
                Some(t) => t as u32,
                None => {
                    types.push(name);
                    types.len() as u32 - 1
                }
            };
            match (own_types, kind) {
                (Some((names, ids)), None) => {
                    let map: Vec<u32> = names.iter().map(|n| type_of(n.clone())).collect();
                    typeid.extend(ids.iter().map(|&t| map[t as usize]));
                }
                _ => {
                    let name = kind
                        .clone()
                        .or_else(|| colour.clone())
                        .unwrap_or_else(|| "A".into());
                    let t = type_of(name);
                    typeid.extend(std::iter::repeat_n(t, n));
                }
            }
            tables.push((placed.len(), what, line));
            placed.extend_from_slice(&discs);
            colours.extend(std::iter::repeat_n(rgb, n));
            Ok::<(), ScenarioError>(())
        };
        // Particles get their ids in the order their tables appear in the file.
        let mut entries: Vec<(usize, Entry)> = Vec::new();
        entries.extend(
            self.gas
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Gas(k))),
        );
        entries.extend(
            self.lattice
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Lattice(k))),
        );
        entries.extend(
            self.block
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Block(k))),
        );
        entries.extend(
            self.disc
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::Disc(k))),
        );
        entries.extend(
            self.file
                .iter()
                .enumerate()
                .map(|(k, g)| (g.span().start, Entry::File(k))),
        );
        entries.sort_by_key(|&(start, _)| start);
        let mut left_out = false;
        for (start, entry) in entries {
            let line = lines.at(start);
            if skip.contains(&line) {
                left_out = true;
                continue;
            }
            match entry {
                Entry::Gas(k) => {
                    let spec = self.gas[k].get_ref();
                    let speeds = match (spec.speed, spec.temperature, spec.uniform) {
                        (Some(v), _, _) => Speeds::Fixed(v),
                        (_, Some(t), _) => Speeds::Temperature(t),
                        (_, _, Some(a)) => Speeds::Uniform(a),
                        _ => Speeds::Fixed(0.0),
                    };
                    let gas = Gas {
                        count: spec.count,
                        radius: spec.radius.range(),
                        region: spec.region.map(|r| (r.min, r.max)),
                        speeds,
                        drift: spec.drift,
                        seed: spec.seed,
                    };
                    let placement = match spec.placement {
                        Placement::Random => scene::gas_among(&gas, &config, &placed),
                        Placement::Lattice => scene::packed_gas(&gas, &config, &placed),
                    };
                    let mut discs = match placement {
                        Ok(discs) => discs,
                        Err(e) => {
                            problems.push(Problem {
                                line: Some(line),
                                message: format!("gas #{}: {e}", k + 1),
                            });
                            continue;
                        }
                    };
                    if spec.zero_momentum {
                        scene::zero_momentum(&mut discs, &config, spec.drift);
                    }
                    if spec.streaming {
                        for d in &mut discs {
                            let flow = config.boundary.streaming_velocity(d.position[1]);
                            d.velocity[0] += flow.unwrap_or(0.0);
                        }
                    }
                    if spec.spin != 0.0 {
                        scene::spin(&mut discs, spec.spin, spec.seed);
                    }
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("gas #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::Lattice(k) => {
                    let spec = self.lattice[k].get_ref();
                    let mut discs = scene::lattice(&Lattice {
                        origin: spec.origin,
                        spacing: spec.spacing,
                        counts: spec.counts,
                        radius: spec.radius,
                        velocity: spec.velocity,
                    });
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("lattice #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::Block(k) => {
                    let spec = self.block[k].get_ref();
                    let law = Law::new(&config);
                    let spacing = block_spacing(spec, &law);
                    let mut discs = scene::lattice(&Lattice {
                        origin: [spec.min[0] + spec.radius, spec.min[1] + spec.radius],
                        spacing: [spacing, spacing],
                        counts: block_counts(spec, &law),
                        radius: spec.radius,
                        velocity: spec.velocity,
                    });
                    tag(&mut discs, spec.tag);
                    add(
                        discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("block #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
                Entry::File(k) => {
                    let spec = self.file[k].get_ref();
                    let read = match self.read_file(spec, &config) {
                        Ok(read) => read,
                        Err(e) => {
                            problems.push(Problem {
                                line: Some(line),
                                message: format!("file #{}: {e}", k + 1),
                            });
                            continue;
                        }
                    };
                    add(
                        read.discs,
                        (&spec.color, &spec.kind),
                        line,
                        format!("file #{} ({})", k + 1, spec.path),
                        &mut placed,
                        Some((&read.types, &read.typeid)),
                    )?;
                }
                Entry::Disc(k) => {
                    let spec = self.disc[k].get_ref();
                    let disc = Particle {
                        mass: spec.mass,
                        angular_velocity: spec.angular_velocity,
                        tag: spec.tag,
                        ..Particle::new(spec.position, spec.velocity, spec.radius)
                    };
                    add(
                        vec![disc],
                        (&spec.color, &spec.kind),
                        line,
                        format!("disc #{}", k + 1),
                        &mut placed,
                        None,
                    )?;
                }
            }
        }
        // Into the world at once (one at a time, each addition re-measured the world: a
        // table per disc took `O(N²)`); an invalid disc is named by its table, and left out
        // so that the rest are checked too.
        add_valid(&mut world, placed, &mut tables, &mut problems);
        // With tables or discs left out, ids are not the ones a run would give: not named.
        let ids = !left_out && problems.is_empty();
        problems.extend(overlapping(&world, &tables, ids));
        if !problems.is_empty() {
            return Err(ScenarioError {
                file: file.to_string(),
                problems,
            });
        }
        let emitted = self
            .emitter
            .iter()
            .map(|e| {
                let e = e.get_ref();
                let name = e
                    .kind
                    .clone()
                    .or_else(|| e.color.clone())
                    .unwrap_or_else(|| "A".into());
                let t = match types.iter().position(|t| *t == name) {
                    Some(t) => t,
                    None => {
                        types.push(name);
                        types.len() - 1
                    }
                };
                let rgb = e.color.as_deref().and_then(|c| parse_colour(c).ok());
                (rgb, t as u32)
            })
            .collect();
        Ok(Built {
            world,
            colours,
            types,
            typeid,
            emitted,
        })
    }
}

/// What of `config` the placement can check discs against when the whole is refused (a
/// problem already reported): its box, collision distance, mass model and obstacles where
/// those are sound, the rest at their defaults.
fn placement_config(config: &Config) -> Config {
    let geometry = Config {
        boundary: config.boundary.clone(),
        collision_radius_scale: config.collision_radius_scale,
        mass_model: config.mass_model,
        obstacles: config.obstacles.clone(),
        ..Config::default()
    };
    if geometry.validate().is_ok() {
        geometry
    } else {
        Config {
            boundary: config.boundary.clone(),
            ..Config::default()
        }
    }
}

/// The invalid discs a table may report before the rest are counted.
const INVALID_PER_TABLE: usize = 3;

/// Adds `placed` to `world`, leaving out and reporting each invalid disc (the first few of a
/// table, then their count); `tables` (each table's first index, name and line) is moved to
/// the discs kept.
fn add_valid(
    world: &mut World,
    placed: Vec<Particle>,
    tables: &mut [(usize, String, usize)],
    problems: &mut Vec<Problem>,
) {
    let total = placed.len();
    let table_of =
        |i: usize, tables: &[(usize, String, usize)]| tables.partition_point(|t| t.0 <= i) - 1;
    let mut invalid: Vec<usize> = Vec::new();
    let mut per_table = vec![0usize; tables.len()];
    let mut from = 0;
    while from < total {
        // All or nothing: on the first invalid disc the world is unchanged, so add the valid
        // ones before it and go on after it.
        let Err((k, e)) = world.add_particles(placed[from..].iter().copied()) else {
            break;
        };
        let i = from + k;
        world
            .add_particles(placed[from..i].iter().copied())
            .expect("the discs before the first invalid one are valid");
        let t = table_of(i, tables);
        per_table[t] += 1;
        let (start, what, line) = &tables[t];
        if per_table[t] <= INVALID_PER_TABLE {
            let n = tables.get(t + 1).map_or(total, |next| next.0) - start;
            problems.push(Problem {
                line: Some(*line),
                message: format!("{what}: particle {} of {n}: {e}", i - start + 1),
            });
        }
        invalid.push(i);
        from = i + 1;
    }
    for (t, &count) in per_table.iter().enumerate() {
        if count > INVALID_PER_TABLE {
            let (_, what, line) = &tables[t];
            problems.push(Problem {
                line: Some(*line),
                message: format!(
                    "{what}: {} more invalid particles",
                    count - INVALID_PER_TABLE
                ),
            });
        }
    }
    // The tables' first indices among the discs kept.
    for table in tables.iter_mut() {
        table.0 -= invalid.partition_point(|&i| i < table.0);
    }
}

/// Discs that start overlapping (closer than their collision distance, not just touching),
/// named by their tables: at most one problem per pair of tables.
fn overlapping(world: &World, tables: &[(usize, String, usize)], ids: bool) -> Vec<Problem> {
    let law = Law::new(world.config());
    let table_of = |id: u32| {
        let k = tables.partition_point(|t| t.0 <= id as usize) - 1;
        &tables[k]
    };
    let mut seen = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for (a, b) in world.colliding_pairs() {
        let (pa, pb) = (
            world.particle(a).expect("listed"),
            world.particle(b).expect("listed"),
        );
        let (dx, dy) = (
            pa.position[0] - pb.position[0],
            pa.position[1] - pb.position[1],
        );
        let gap = law.collision_distance(pa.radius, pb.radius) - (dx * dx + dy * dy).sqrt();
        // Only real overlaps (a lattice of touching discs is fine); the minimum image of a
        // periodic box is left to the grid, which found the pair.
        if gap <= 1e-9 * law.collision_distance(pa.radius, pb.radius) {
            continue;
        }
        let (ta, tb) = (table_of(a.0), table_of(b.0));
        // A file holds the overlaps of the run that wrote it; the first step resolves them.
        if ta.0 == tb.0 && ta.1.starts_with("file") {
            continue;
        }
        if !seen.insert((ta.0, tb.0)) {
            continue;
        }
        // ", discs 3 and 7": which two, where the ids are the ones a run would give.
        let which = if ids {
            format!(" (discs {} and {})", a.0, b.0)
        } else {
            String::new()
        };
        let message = if ta.0 == tb.0 {
            format!(
                "{}: two of its discs{which} overlap by {gap:.3} (spacing below the collision \
                 distance)",
                ta.1
            )
        } else {
            format!(
                "{} (line {}) and {} (line {}) overlap{which} by {gap:.3}; move one or let a \
                 [[gas]] come later (generators keep clear of earlier tables)",
                ta.1, ta.2, tb.1, tb.2
            )
        };
        out.push(Problem {
            line: Some(tb.2),
            message,
        });
        if out.len() >= 10 {
            break;
        }
    }
    out
}

/// A particle table, for building in file order.
#[derive(Clone, Copy)]
enum Entry {
    Gas(usize),
    Lattice(usize),
    Block(usize),
    Disc(usize),
    File(usize),
}

/// What the first step or the first output would refuse in a built world, found before the
/// run: the energy in the gravity field beyond f64, a time step that needs more substeps
/// than a step may take, a state beyond a GSD frame's 32-bit floats. So `check` finds them.
fn start_problems(scenario: &Scenario, world: &World, source: &str) -> Vec<Problem> {
    let mut problems = Vec::new();
    if !crate::analysis::mechanical_energy(world).is_finite() {
        problems.push(Problem {
            line: line_of_key(source, "world", "gravity"),
            message: format!(
                "world.gravity: the potential energy in the gravity field overflows f64 at the \
                 start (gravity {:?} is too strong for these positions)",
                world.config().gravity
            ),
        });
    }
    let p = world.particles();
    let max_speed2 = (0..p.len())
        .map(|i| p.vx()[i] * p.vx()[i] + p.vy()[i] * p.vy()[i])
        .fold(0.0, f64::max);
    let min_radius = p.radius().iter().copied().fold(f64::INFINITY, f64::min);
    let dt = scenario.time.dt;
    if !p.is_empty()
        && world.substeps_for_extremes(dt, max_speed2, min_radius) > bounce::MAX_SUBSTEPS
    {
        problems.push(Problem {
            line: line_of_key(source, "time", "max_travel"),
            message: format!(
                "time.max_travel: dt {dt} needs more than {} substeps to keep the fastest disc \
                 within max_travel {} of the smallest radius per substep at the start: lower \
                 dt or raise max_travel",
                bounce::MAX_SUBSTEPS,
                world.config().max_travel.unwrap_or(0.0)
            ),
        });
    }
    #[cfg(not(target_arch = "wasm32"))]
    if scenario.output.gsd_every > 0
        && let Err(e) = crate::gsd::fits_frame(world)
    {
        problems.push(Problem {
            line: line_of_key(source, "output", "gsd_every"),
            message: format!("output.gsd_every: the first frame cannot be written: {e}"),
        });
    }
    problems
}

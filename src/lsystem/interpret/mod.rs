//! The interpreter: the 3-D turtle reads a derived [`ModuleString`] and draws a
//! [`Skeleton`], with the frame rotations of [`crate::geom::Frame`].

use crate::error::{Error, Result};
use crate::geom::{Frame, cos_sin_deg};
use crate::lsystem::grammar::{POP, PUSH};
use crate::lsystem::query::Asked;
use crate::lsystem::{LSystem, LsystemOptions, ModuleString};
use crate::progress::{Run, Stage};
use crate::skeleton::{
    Branch, LeafSite, NO_PARENT, Polygon, Skeleton, SkeletonParts, assign_axis_orders,
};
use glam::DVec3;
use rules::{Derivation, Work, walk_with_rules};

mod rules;

/// What a symbol means to the turtle.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Ignore,
    Elasticity,
    /// `@O` (sphere) or `@o` / `@c` (disc).
    Organ(u32),
    /// `;` (+1) and `,` (-1): the colour index.
    Color(i32),
    /// `~x` of a surface the view file defines: index into `LSystem::surfaces`.
    Surface(u32),
    Draw,
    Move,
    Turn(f64),
    Pitch(f64),
    Roll(f64),
    TurnAround,
    RollHorizontal,
    MoveTo,
    SetHeading,
    Width(f64),
    Push,
    Pop,
    Cut,
    PolygonStart,
    PolygonVertex,
    PolygonEnd,
    Leaf,
    CylinderStart,
    CylinderPoint,
    CylinderEnd,
}

fn op_of(name: &str) -> Op {
    match name {
        "F" | "G" => Op::Draw,
        "f" | "g" => Op::Move,
        "+" => Op::Turn(1.0),
        "-" => Op::Turn(-1.0),
        "&" => Op::Pitch(1.0),
        "^" => Op::Pitch(-1.0),
        "/" => Op::Roll(1.0),
        "\\" => Op::Roll(-1.0),
        "|" => Op::TurnAround,
        "$" | "@v" => Op::RollHorizontal,
        "@M" => Op::MoveTo,
        "@R" => Op::SetHeading,
        "!" => Op::Width(-1.0),
        "#" => Op::Width(1.0),
        "[" => Op::Push,
        "]" => Op::Pop,
        "%" => Op::Cut,
        "{" => Op::PolygonStart,
        "." => Op::PolygonVertex,
        "}" => Op::PolygonEnd,
        // `~` alone, or `~x` (cpfg's predefined surface x): a surface site.
        n if n.starts_with('~') => Op::Leaf,
        "_" => Op::Elasticity,
        "@O" => Op::Organ(crate::skeleton::ORGAN_SPHERE),
        "@o" | "@c" => Op::Organ(crate::skeleton::ORGAN_DISC),
        ";" => Op::Color(1),
        "," => Op::Color(-1),
        "@Gs" => Op::CylinderStart,
        "@Gc" => Op::CylinderPoint,
        "@Ge" => Op::CylinderEnd,
        _ => Op::Ignore,
    }
}

#[derive(Clone, Copy)]
struct State {
    frame: Frame,
    width: f64,
    /// The last branch drawn on this axis, or NO_PARENT after a move without drawing.
    parent: u32,
    /// The heading that branch was drawn with.
    parent_heading: DVec3,
    /// The generalized cylinder (`@Gs` … `@Ge`) being drawn: an index into
    /// `Turtle::cylinders`, or NO_PARENT.
    cylinder: u32,
    /// The elasticity of the view file's older tropism (`_` changes it).
    elasticity: f64,
    /// The colour index (`;` and `,` change it).
    color: u32,
}

struct Turtle {
    ops: Vec<Op>,
    angle: f64,
    width_increment: f64,
    step_size: f64,
    tropism: Option<(DVec3, f64)>,
    old_tropism: Option<crate::lsystem::grammar::OldTropism>,
    past_cut: bool,
    max_branches: usize,
    /// Cosine and sine of recently used angles (grammars reuse a few angles).
    trig: [(u64, (f64, f64)); 8],
    /// Turn jitter in degrees and its generator.
    jitter: f64,
    rng: crate::rng::Rng,
    state: State,
    stack: Vec<State>,
    /// While > 0, modules are skipped by `%` up to the end of the branch.
    cutting: Option<usize>,
    polygons: Vec<(Vec<[f32; 3]>, u32, u32)>,
    branches: Vec<Branch>,
    cos_to_parent: Vec<f64>,
    /// The turtle's up vector when each branch was drawn.
    ups: Vec<[f32; 3]>,
    /// The branches drawn inside each generalized cylinder, in drawing order.
    cylinders: Vec<Vec<u32>>,
    leaves: Vec<LeafSite>,
    closed: Vec<Polygon>,
    points: Vec<[f32; 3]>,
    organs: Vec<crate::skeleton::Organ>,
    surfaces: std::sync::Arc<[crate::lsystem::surface::Surface]>,
    /// The colour index of each branch.
    colors: Vec<u32>,
    /// Whether `;` or `,` appeared (else no colours are kept).
    colored: bool,
    color_increment: u32,
}

fn v3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

impl Turtle {
    /// Room for more branches (as many again, at least 1,024) in the per-branch arrays, or
    /// `OutOfMemory` instead of an abort.
    #[cold]
    #[inline(never)]
    fn grow_branches(&mut self) -> Result<()> {
        let (n, more) = (self.branches.len(), self.branches.len().max(1024));
        crate::limits::try_room(
            &mut [
                &mut self.branches,
                &mut self.cos_to_parent,
                &mut self.ups,
                &mut self.colors,
            ],
            more,
            false,
            || format!("the skeleton's branches ({n} and more)"),
        )
    }

    #[inline]
    fn cos_sin(&mut self, degrees: f64) -> (f64, f64) {
        let bits = degrees.to_bits();
        let slot = &mut self.trig[(bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 61) as usize];
        if slot.0 != bits {
            *slot = (bits, cos_sin_deg(degrees));
        }
        slot.1
    }

    fn polygon_point(&mut self) {
        let p = v3(self.state.frame.position);
        if let Some((points, _, _)) = self.polygons.last_mut() {
            if points.last() != Some(&p) {
                points.push(p);
            }
        }
    }

    /// `F`/`G` (`draw`) or `f`/`g`: a step of `length` (the step size if none).
    fn draw(&mut self, draw: bool, length: Option<f64>, birth: u32, step: u32) -> Result<()> {
        let length = length.unwrap_or(self.step_size);
        if let Some((t, e)) = self.tropism {
            if draw {
                self.state.frame.bend(t, e);
            }
        }
        let start = self.state.frame.position;
        let end = self.state.frame.forward(length);
        // The older tropism bends after `f` and `g` too, as cpfg bends after every step.
        if let Some(t) = self.old_tropism {
            if self.state.elasticity != 0.0 {
                self.state
                    .frame
                    .bend_old_style(t.direction, self.state.elasticity);
            }
        }
        let bound = crate::limits::MAX_COORDINATE as f64;
        if !end.is_finite() || end.abs().max_element() > bound {
            return Err(Error::Eval {
                step,
                message: format!("the turtle left the f32 range (at {end}); shorten the steps"),
            });
        }
        if !self.polygons.is_empty() {
            // Inside `{ }` a move only traces the polygon: the turtle has left the
            // end of its last branch, so what is drawn next starts a new root.
            self.polygon_point();
            self.state.parent = NO_PARENT;
        } else if draw {
            if self.branches.len() >= self.max_branches {
                return Err(Error::LimitExceeded {
                    limit_name: "max_branches",
                    what: "branches",
                    limit: self.max_branches as u64,
                    requested: self.branches.len() as u64 + 1,
                    step: Some(step),
                });
            }
            let radius = (self
                .state
                .width
                .clamp(0.0, crate::limits::MAX_COORDINATE as f64)
                * 0.5) as f32;
            self.branches.push(Branch {
                start: v3(start),
                end: v3(end),
                start_radius: radius,
                end_radius: radius,
                parent: self.state.parent,
                birth,
                order: 0,
                flags: 0,
            });
            let heading = self.state.frame.heading;
            self.ups.push(self.state.frame.up.as_vec3().to_array());
            self.colors.push(self.state.color);
            if self.state.cylinder != NO_PARENT {
                let b = (self.branches.len() - 1) as u32;
                self.cylinders[self.state.cylinder as usize].push(b);
            }
            self.cos_to_parent
                .push(heading.dot(self.state.parent_heading));
            self.state.parent = (self.branches.len() - 1) as u32;
            self.state.parent_heading = heading;
        } else {
            self.state.parent = NO_PARENT;
        }

        Ok(())
    }

    /// `@M(x, y, z)`: moves the turtle without drawing (a missing coordinate stays).
    fn move_to(&mut self, at: [Option<f64>; 3], step: u32) -> Result<()> {
        let p = self.state.frame.position;
        let to = DVec3::new(
            at[0].unwrap_or(p.x),
            at[1].unwrap_or(p.y),
            at[2].unwrap_or(p.z),
        );
        if to.abs().max_element() > crate::limits::MAX_COORDINATE as f64 {
            return Err(Error::Eval {
                step,
                message: format!("@M moves the turtle to {to}, past 1e15 units; shorten the moves"),
            });
        }
        self.state.frame.position = to;
        self.state.parent = NO_PARENT;
        if !self.polygons.is_empty() {
            self.polygon_point();
        }

        Ok(())
    }

    /// `@O(d)`, `@o(d)`, `@c(d)`: a sphere or disc of diameter `size` (the width if none).
    /// A negative diameter draws the organ of its magnitude, as cpfg's (its functions can
    /// dip a hair below 0).
    fn organ(&mut self, kind: u32, size: Option<f64>, birth: u32, step: u32) -> Result<()> {
        let size = size.unwrap_or(self.state.width).abs();
        if !(size.is_finite() && size <= crate::limits::MAX_COORDINATE as f64) {
            return Err(Error::Eval {
                step,
                message: format!("a sphere or disc of diameter {size}; expected a finite size"),
            });
        }
        self.organs.push(crate::skeleton::Organ {
            position: v3(self.state.frame.position),
            heading: v3(self.state.frame.heading),
            up: v3(self.state.frame.up),
            size: size as f32,
            kind,
            branch: self.state.parent,
            birth,
            color: self.state.color,
        });

        Ok(())
    }

    /// `~x(s)`: the view file's surface `k`, scaled by `scale`, as triangles.
    fn surface(&mut self, k: usize, scale: Option<f64>, birth: u32, step: u32) -> Result<()> {
        let s = &self.surfaces[k];
        let scale = s.scale * scale.unwrap_or(1.0);
        let f = self.state.frame;
        if self.closed.len() + s.triangles.len() > self.max_branches {
            return Err(Error::LimitExceeded {
                limit_name: "max_branches",
                what: "branches and surface triangles",
                limit: self.max_branches as u64,
                requested: (self.closed.len() + s.triangles.len()) as u64,
                step: Some(step),
            });
        }
        // The copy lies within `radius * scale` of the turtle: one check for all of it.
        let reach = f.position.abs().max_element() + s.radius * scale.abs();
        if !(reach.is_finite() && reach <= crate::limits::MAX_COORDINATE as f64) {
            return Err(Error::Eval {
                step,
                message: format!(
                    "surface `~{}` scaled by {scale} leaves the f32 range",
                    s.name
                ),
            });
        }
        let first = self.points.len() as u32;
        self.closed
            .extend((0..s.triangles.len() as u32).map(|k| Polygon {
                first: first + 3 * k,
                count: 3,
                branch: self.state.parent,
                birth,
            }));
        self.points.extend(
            s.triangles
                .iter()
                .flatten()
                .map(|p| v3(f.position + (f.heading * p.x + f.up * p.y + f.left * p.z) * scale)),
        );
        // The turtle moves on to the surface's end point (cpfg), leaving its branch as a
        // move does when that is elsewhere.
        let e = s.end;
        if e != DVec3::ZERO {
            let to = f.position + (f.left * e.x + f.heading * e.y + f.up * e.z) * scale;
            if !to.is_finite() || to.abs().max_element() > crate::limits::MAX_COORDINATE as f64 {
                return Err(Error::Eval {
                    step,
                    message: format!(
                        "surface `~{}` moves the turtle out of the f32 range",
                        s.name
                    ),
                });
            }
            self.state.frame.position = to;
            self.state.parent = NO_PARENT;
        }
        Ok(())
    }

    /// `}`: closes the innermost polygon (kept when it has three points or more).
    fn close_polygon(&mut self) {
        if let Some((points, branch, birth)) = self.polygons.pop() {
            if points.len() >= 3 {
                self.closed.push(Polygon {
                    first: self.points.len() as u32,
                    count: points.len() as u32,
                    branch,
                    birth,
                });
                self.points.extend_from_slice(&points);
            }
        }
    }

    fn module(&mut self, sym: u16, params: &[f32], birth: u32, step: u32) -> Result<()> {
        let op = self.ops[sym as usize];
        if let Some(depth) = self.cutting.as_mut() {
            match op {
                Op::Push => *depth += 1,
                Op::Pop if *depth == 0 => self.cutting = None,
                Op::Pop => *depth -= 1,
                _ => {}
            }
            if self.cutting.is_some() {
                return Ok(());
            }
        }
        let arg = |k: usize| params.get(k).map(|&v| v as f64);
        let mut angle = arg(0).unwrap_or(self.angle);
        if self.jitter > 0.0 && matches!(op, Op::Turn(_) | Op::Pitch(_) | Op::Roll(_)) {
            angle += (self.rng.next_f64() * 2.0 - 1.0) * self.jitter;
        }
        match op {
            Op::Ignore => {}
            Op::Draw | Op::Move => self.draw(op == Op::Draw, arg(0), birth, step)?,
            Op::Turn(s) => {
                let cs = self.cos_sin(angle * s);
                self.state.frame.turn(cs)
            }
            Op::Pitch(s) => {
                let cs = self.cos_sin(angle * s);
                self.state.frame.pitch(cs)
            }
            Op::Roll(s) => {
                let cs = self.cos_sin(angle * s);
                self.state.frame.roll(cs)
            }
            Op::TurnAround => self.state.frame.turn_around(),
            Op::RollHorizontal => self.state.frame.roll_horizontal(),
            Op::MoveTo => self.move_to([arg(0), arg(1), arg(2)], step)?,
            Op::SetHeading => {
                if params.len() >= 3 {
                    let v = |k: usize| params[k] as f64;
                    let h = DVec3::new(v(0), v(1), v(2));
                    let up = (params.len() >= 6).then(|| DVec3::new(v(3), v(4), v(5)));
                    self.state.frame.set_heading(h, up);
                }
            }
            Op::Width(s) => {
                self.state.width = match arg(0) {
                    Some(w) => w,
                    None => (self.state.width + s * self.width_increment).max(0.0),
                }
            }
            Op::Push => self.stack.push(self.state),
            Op::Organ(kind) => self.organ(kind, arg(0), birth, step)?,
            Op::Surface(k) => self.surface(k as usize, arg(0), birth, step)?,
            Op::Color(sign) => {
                self.colored = true;
                self.state.color = match arg(0) {
                    Some(c) if c.is_finite() => c.clamp(0.0, u32::MAX as f64) as u32,
                    _ if sign > 0 => self.state.color.saturating_add(self.color_increment),
                    _ => self.state.color.saturating_sub(self.color_increment),
                };
            }
            Op::Elasticity => {
                let inc = self.old_tropism.map_or(0.0, |t| t.increment);
                self.state.elasticity = arg(0).unwrap_or(self.state.elasticity + inc);
            }
            Op::CylinderStart => {
                self.state.cylinder = self.cylinders.len() as u32;
                self.cylinders.push(Vec::new());
            }
            // Every drawn internode's end is a control point of the cylinder's curve.
            Op::CylinderPoint => {}
            Op::CylinderEnd => self.state.cylinder = NO_PARENT,
            Op::Pop => {
                if let Some(s) = self.stack.pop() {
                    self.state = s;
                }
            }
            // `interpretation past %: on` (cpfg's default) draws past a cut the last step
            // made; `off` skips the rest of its branch.
            Op::Cut if self.past_cut => {}
            Op::Cut => self.cutting = Some(0),
            Op::PolygonStart => {
                self.polygons.push((Vec::new(), self.state.parent, birth));
                self.polygon_point();
            }
            Op::PolygonVertex => self.polygon_point(),
            Op::PolygonEnd => self.close_polygon(),
            Op::Leaf => self.leaves.push(LeafSite {
                position: v3(self.state.frame.position),
                heading: v3(self.state.frame.heading),
                up: v3(self.state.frame.up),
                branch: self.state.parent,
                birth,
            }),
        }
        Ok(())
    }
}

/// Reads `string` with the turtle into a skeleton: each `F`/`G` a branch whose parent is
/// the last branch drawn on the same axis (none after a move without drawing), whose depth
/// is the step that produced the module, and whose order follows
/// [`assign_axis_orders`]. Interpretation rules expand modules for the turtle only.
/// Reads `string` with the turtle, reporting to `progress`.
///
/// Interpretation rules spend from the work budget the derivation left (`max_work` for
/// a string that was not derived here).
pub(crate) fn interpret_with<'p>(
    ls: &'p LSystem,
    string: &ModuleString,
    options: &LsystemOptions,
    mut progress: Run<'p>,
) -> Result<Skeleton> {
    let max_work = options.max_work as u64;
    let mut budget = string.work_left.map_or(max_work, |w| w.min(max_work));
    let work = Work {
        progress: &mut progress,
        budget: &mut budget,
        derivation: None,
    };
    interpret_answering(ls, string, options, None, work)
}

/// cpfg's query modules: the turtle reads `string` and each `?P(x,y[,z])` (and `?H`,
/// `?U`, `?L`) gets the position (heading, up, left) the turtle has there, in as many of
/// its parameters as it has. Run after every derivation step, as cpfg does, so the next
/// step's productions see the answers.
///
/// The walk spends from the derivation's work budget, `fx` (its interpretation rules as
/// they run), and its progress callback hears it.
pub(crate) fn answer_queries<'p>(
    ls: &'p LSystem,
    string: &mut ModuleString,
    options: &LsystemOptions,
    fx: &mut super::stmt::Effects<'p>,
    step: u32,
) -> Result<()> {
    let mut asked = Asked::new(ls);
    let mut progress = std::mem::take(&mut fx.progress);
    let mut budget = fx.budget;
    let work = Work {
        progress: &mut progress,
        budget: &mut budget,
        derivation: Some(Derivation {
            step,
            fraction: fx.fraction,
        }),
    };
    let r = interpret_answering(ls, string, options, Some(&mut asked), work);
    fx.progress = progress;
    fx.reset_budget(budget);
    r?;
    asked.answer(string);
    Ok(())
}

fn interpret_answering<'p>(
    ls: &'p LSystem,
    string: &ModuleString,
    options: &LsystemOptions,
    mut asked: Option<&mut Asked>,
    mut work: Work<'_, 'p>,
) -> Result<Skeleton> {
    // Answering a derivation's queries, the walk reports as the derivation (its rules'
    // work only), not as an interpretation.
    let interpreting = work.derivation.is_none();
    let n = string.len().max(1) as f64;
    let answering = asked.is_some();
    // Only what the queries need: the walk up to the last one, past branches without
    // (not through interpretation rules, nor when turns draw random jitter).
    let jitters = options.turn_jitter > 0.0;
    let only_asked = answering && ls.homomorphism.is_empty() && !jitters;
    let mut skip = Vec::new();
    let end = match asked.as_deref() {
        Some(a) if only_asked => a.plan(string, &mut skip),
        _ => 0,
    };
    let mut ask = |i: usize, frame: &Frame| {
        if let Some(asked) = asked.as_deref_mut() {
            asked.ask(string, i, frame);
        }
    };
    options.validate()?;
    let mut t = Turtle::new(ls, options);
    debug_assert_eq!(t.ops[PUSH as usize], Op::Push);
    debug_assert_eq!(t.ops[POP as usize], Op::Pop);
    // Without interpretation rules every F and G is one branch: size the arrays once (the
    // turtle never pushes past this; with rules, the sink below makes room as it goes).
    let draws = string
        .syms
        .iter()
        .filter(|&&s| t.ops[s as usize] == Op::Draw)
        .count()
        .min(options.max_branches);
    crate::limits::try_room(
        &mut [
            &mut t.branches,
            &mut t.cos_to_parent,
            &mut t.ups,
            &mut t.colors,
        ],
        draws,
        true,
        || format!("the skeleton's branches ({draws})"),
    )?;
    if !answering && ls.homomorphism.is_empty() && !t.surfaces.is_empty() {
        // Room for every surface's triangles at once (a string of many leaves makes
        // millions of points: growing by doubling copies them and faults twice).
        let tris: usize = string
            .syms
            .iter()
            .map(|&s| match t.ops[s as usize] {
                Op::Surface(k) => t.surfaces[k as usize].triangles.len(),
                _ => 0,
            })
            .sum::<usize>()
            .min(options.max_branches);
        crate::limits::try_room(&mut [&mut t.closed], tris, true, || {
            format!("the skeleton's surface triangles ({tris})")
        })?;
        crate::limits::try_room(&mut [&mut t.points], 3 * tris, true, || {
            format!("the skeleton's surface points ({})", 3 * tris)
        })?;
    }
    if only_asked {
        let mut i = 0;
        while i < end {
            match skip[i] {
                u32::MAX => {
                    let birth = string.birth(i);
                    ask(i, &t.state.frame);
                    t.module(string.symbol(i), string.params(i), birth, birth)?;
                    i += 1;
                }
                close => i = close as usize + 1,
            }
        }
    } else if ls.homomorphism.is_empty() {
        for i in 0..string.len() {
            if i % crate::progress::EVERY == 0 && interpreting {
                work.progress.report(Stage::Interpretation, i as f64 / n)?;
            }
            let birth = string.birth(i);
            ask(i, &t.state.frame);
            t.module(string.symbol(i), string.params(i), birth, birth)?;
        }
    } else {
        walk_with_rules(&mut t, ls, string, options, work.reborrow(), &mut ask)?;
    }
    if interpreting {
        work.progress.report(Stage::Interpretation, 1.0)?;
    }
    if answering {
        // Answering queries wants the turtle's walk, not a skeleton.
        return Ok(Skeleton::default());
    }
    Ok(t.into_skeleton())
}

impl Turtle {
    /// A turtle at the origin, heading up, with the grammar's view settings and `options`.
    fn new(ls: &LSystem, options: &LsystemOptions) -> Turtle {
        let view = ls.view;
        let initial_width = options.initial_width.unwrap_or(view.initial_width);
        let mut t = Turtle {
            ops: ls.symbols.names.iter().map(|n| op_of(n)).collect(),
            angle: options.angle_increment.unwrap_or(view.angle_increment),
            width_increment: options.width_increment.unwrap_or(view.width_increment),
            step_size: view.step_size,
            tropism: view.tropism,
            // Without `tropism direction:` cpfg's tropism vector is (0, 1, 0), so `_(e)`
            // alone bends toward +Y.
            old_tropism: Some(
                view.old_tropism
                    .unwrap_or(crate::lsystem::grammar::OldTropism {
                        direction: DVec3::Y,
                        elasticity: 0.0,
                        increment: 0.0,
                    }),
            ),
            past_cut: view.interpretation_past_cut,
            max_branches: options.max_branches,
            // NaN bits never equal an angle's, so every slot starts empty.
            trig: [(f64::NAN.to_bits(), (1.0, 0.0)); 8],
            jitter: options.turn_jitter,
            // A stream of its own, so jitter does not change what derivation draws.
            rng: crate::rng::Rng::new(ls.effective_seed(options) ^ 0x005E_ED7A_110F_7EE5),
            state: State {
                frame: Frame::default(),
                width: initial_width,
                parent: NO_PARENT,
                parent_heading: DVec3::Y,
                cylinder: NO_PARENT,
                elasticity: view.old_tropism.map_or(0.0, |t| t.elasticity),
                color: view.initial_color,
            },
            stack: Vec::new(),
            cutting: None,
            polygons: Vec::new(),
            branches: Vec::new(),
            cos_to_parent: Vec::new(),
            ups: Vec::new(),
            cylinders: Vec::new(),
            leaves: Vec::new(),
            closed: Vec::new(),
            points: Vec::new(),
            organs: Vec::new(),
            surfaces: ls.surfaces.clone(),
            colors: Vec::new(),
            colored: false,
            color_increment: view.color_increment,
        };
        // `~x` with a surface from the view file draws the surface.
        for (sym, name) in ls.symbols.names.iter().enumerate() {
            let mut c = name.chars();
            if let (Some('~'), Some(x), None) = (c.next(), c.next(), c.next()) {
                if let Some(k) = ls.surfaces.iter().position(|s| s.name == x) {
                    t.ops[sym] = Op::Surface(k as u32);
                }
            }
        }
        t
    }

    /// The skeleton the walk drew.
    fn into_skeleton(self) -> Skeleton {
        let mut t = self;
        assign_axis_orders(&mut t.branches, &t.cos_to_parent);
        // Every point was checked to be finite and within the f32 range as it was made.
        let curves = cylinder_curves(&t.branches, &t.cylinders);
        Skeleton::from_trusted(SkeletonParts {
            branches: t.branches,
            leaves: t.leaves,
            polygons: t.closed,
            polygon_points: t.points,
            ups: t.ups,
            curves,
            organs: t.organs,
            colors: if t.colored { t.colors } else { Vec::new() },
        })
    }
}

/// The curves of a grammar's generalized cylinders (`@Gs` … `@Ge`): the internodes drawn
/// inside one form a C¹ chain, each a cubic Bézier whose tangent at a joint with the
/// next internode of the chain is the mean of the two directions (handles a third of the
/// internode long); other branches stay straight. Empty when there are no cylinders.
fn cylinder_curves(branches: &[Branch], cylinders: &[Vec<u32>]) -> Vec<[[f32; 3]; 2]> {
    if cylinders.iter().all(|c| c.is_empty()) {
        return Vec::new();
    }
    let dir = |b: &Branch| {
        (glam::Vec3::from(b.end) - glam::Vec3::from(b.start)).normalize_or(glam::Vec3::Y)
    };
    let mut curves: Vec<[[f32; 3]; 2]> = branches
        .iter()
        .map(|b| {
            let c = crate::geom::Curve::straight(b.start.into(), b.end.into());
            [c.p1.to_array(), c.p2.to_array()]
        })
        .collect();
    for chain in cylinders {
        for (k, &i) in chain.iter().enumerate() {
            let b = &branches[i as usize];
            let d = dir(b);
            let third = (glam::Vec3::from(b.end) - glam::Vec3::from(b.start)).length() / 3.0;
            // The neighbour in the chain, when it continues this internode's axis.
            let mean = |o: u32| (d + dir(&branches[o as usize])).normalize_or(d);
            let t0 = match k.checked_sub(1).map(|p| chain[p]) {
                Some(p) if b.parent == p => mean(p),
                _ => d,
            };
            let t1 = match chain.get(k + 1) {
                Some(&n) if branches[n as usize].parent == i => mean(n),
                _ => d,
            };
            curves[i as usize] = [
                (glam::Vec3::from(b.start) + t0 * third).to_array(),
                (glam::Vec3::from(b.end) - t1 * third).to_array(),
            ];
        }
    }
    curves
}

//! A species: the parameters of one tree's growth, its presets and their checks.

use crate::error::{Error, Result};

/// One species: how a tree grows. `Default` is the excurrent species' values with neutral
/// apical control; start from it (or `preset`) and change the fields you need. Lengths are
/// world units, angles degrees.
///
/// C: ArborGrowthParams, a struct that grows (see "Structs that grow" in docs/c-api.md):
/// start from arbor_growth_params_default() or arbor_growth_params_preset().
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct GrowthParams {
    /// sizeof(ArborGrowthParams) as the host was compiled (C only; Rust keeps it at its own
    /// size).
    pub(crate) struct_size: u32,
    /// lambda in [0, 1]: 0.5 neutral, above favours the main axis (excurrent), below the
    /// laterals (decurrent). Default 0.5.
    pub apical_control: f32,
    /// alpha > 0: vigour at the base = alpha * light gathered. Default 2.
    pub vigor_multiplier: f32,
    /// Length of an internode at vigour 1, in (0, 10000]. Default 0.25.
    pub internode_length: f32,
    /// Angle between a lateral bud and its internode's heading, 0..=180. Default 45.
    pub branch_angle: f32,
    /// Turn about the heading from one lateral bud to the next, finite. Default 137.5.
    pub phyllotaxis: f32,
    /// eta: weight of up (gravitropism) in a shoot's heading; negative bends down. Finite,
    /// -1..=1. Default 0.1.
    pub tropism: f32,
    /// xi >= 0: weight of the environment's optimal direction. Default 0.25.
    pub environment_weight: f32,
    /// n in [1, 4]: a parent's r^n is the sum of its children's. Default 2.5.
    pub pipe_exponent: f32,
    /// Radius of a branch tip, in (0, 10000]. Default 0.01.
    pub tip_radius: f32,
    /// A lateral branch is shed when its vigour < shed_multiplier * internodes^shed_exponent
    /// (its internodes counted with everything above it). >= 0 (0: never). Default 0.03.
    pub shed_multiplier: f32,
    /// 0..=8. Default 1.3.
    pub shed_exponent: f32,
    /// A branch younger than this many cycles is never shed. Default 4.
    pub shed_delay: u32,
    /// A tree older than this many cycles drops seeds each cycle; 0 (default): never.
    pub seed_age: u32,
    /// Seeds land within ln(root vigour) * seed_spread of the base, >= 0. Default 2.
    pub seed_spread: f32,
    /// Space colonization: half-angle of a bud's perception cone, degrees, in (0, 180].
    /// Default 90.
    pub perception_angle: f32,
    /// Space colonization: reach of the perception cone, in internode lengths, in
    /// (0, 64]. Default 4.
    pub perception_reach: f32,
    /// Space colonization: markers closer than this many internode lengths to a bud are
    /// removed (occupied), 0..=64. Default 2.
    pub occupancy_reach: f32,
    /// Most internodes one shoot grows in a cycle, 1..=64. Default 8.
    pub max_shoot: u32,
    /// Palubicki's shedding: a lateral branch older than `shed_delay` cycles is shed when
    /// the light its buds gather, per internode it carries, is below this (a tree whose
    /// whole light per internode falls below it dies). Light is Q as the environment gives
    /// it (at most `full_light` in a shadow world, 1 with markers). >= 0 (0: off).
    /// Default 0.1. (Added after the first layout.)
    pub shed_light: f32,
    /// Apical control (lambda) of a new tree, in [0, 1]: it moves linearly to
    /// `apical_control` over `maturity_age` cycles. Default 0.5. (Added after the first
    /// layout.)
    pub young_apical_control: f32,
    /// Vigour multiplier (alpha) of a new tree, > 0: it moves linearly to
    /// `vigor_multiplier` over `maturity_age` cycles. Default 2. (Added after the first
    /// layout.)
    pub young_vigor_multiplier: f32,
    /// Growth cycles from planting until a tree has its adult apical control and vigour
    /// multiplier, 0..=10000 (0: adult from the start). Default 0. (Added after the first
    /// layout.)
    pub maturity_age: u32,
    /// A tree this many cycles old grows no more shoots (it still sheds); 0: it never
    /// stops. Default 0. (Added after the first layout.)
    pub max_age: u32,
    /// No internode grows to end higher than this above the tree's base, world units,
    /// >= 0 (0: no limit). Default 0. (Added after the first layout.)
    pub max_height: f32,
    /// Weeping: a lateral axis's tropism falls by this for each internode of the axis
    /// before the new one, so a longer branch hangs more. 0..=1. Default 0. (Added after
    /// the first layout.)
    pub droop: f32,
    /// In a shadow world, a seed of this species grows into a tree only where the light on
    /// the ground is at least this: full light less `shadow_strength` per bud above the
    /// ground there, at any height (buds counted over the 5 x 5 columns of cells around
    /// it, per column; see `shed_light` for the unit). >= 0. Default 0. (Added after the
    /// first layout.)
    pub germination_light: f32,
}

impl Default for GrowthParams {
    fn default() -> Self {
        GrowthParams {
            struct_size: std::mem::size_of::<GrowthParams>() as u32,
            apical_control: 0.5,
            vigor_multiplier: 2.0,
            internode_length: 0.25,
            branch_angle: 45.0,
            phyllotaxis: 137.5,
            tropism: 0.1,
            environment_weight: 0.25,
            pipe_exponent: 2.5,
            tip_radius: 0.01,
            shed_multiplier: 0.03,
            shed_exponent: 1.3,
            shed_delay: 4,
            seed_age: 0,
            seed_spread: 2.0,
            perception_angle: 90.0,
            perception_reach: 4.0,
            occupancy_reach: 2.0,
            max_shoot: 8,
            shed_light: 0.1,
            young_apical_control: 0.5,
            young_vigor_multiplier: 2.0,
            maturity_age: 0,
            max_age: 0,
            max_height: 0.0,
            droop: 0.0,
            germination_light: 0.0,
        }
    }
}

/// Named species with documented parameter values (C: ArborSpecies, for
/// arbor_growth_params_preset(); Rust: `GrowthParams::preset`).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Species {
    /// A conifer-like tree with a strong leader: lambda 0.58, branch angle 65 degrees.
    Excurrent = 0,
    /// A broad, spreading crown: lambda 0.46, alpha 2.2, branch angle 45 degrees.
    Decurrent = 1,
    /// A narrow column: lambda 0.54, branch angle 30 degrees, tropism 0.25.
    Columnar = 2,
    /// A shrub: lambda 0.42, short internodes, branch angle 55 degrees, little shedding.
    Bush = 3,
    /// Drooping shoots: lambda 0.5, tropism -0.25 (shoots bend down).
    Weeping = 4,
}

crate::enums::numbered!(Species as "ArborSpecies" {
    Excurrent = "excurrent",
    Decurrent = "decurrent",
    Columnar = "columnar",
    Bush = "bush",
    Weeping = "weeping",
});

impl GrowthParams {
    /// The parameters of a named species. Values (the rest as [`Default`]):
    ///
    /// | species | lambda | alpha | internode | branch angle | tropism | xi | shed multiplier |
    /// |---|---|---|---|---|---|---|---|
    /// | excurrent | 0.58 | 2 | 0.25 | 65 | 0.15 | 0.2 | 0.03 |
    /// | decurrent | 0.46 | 2.2 | 0.25 | 45 | 0.05 | 0.3 | 0.03 |
    /// | columnar | 0.54 | 2 | 0.25 | 30 | 0.25 | 0.15 | 0.03 |
    /// | bush | 0.42 | 2.4 | 0.15 | 55 | 0.05 | 0.3 | 0.015 |
    /// | weeping | 0.5 | 2 | 0.25 | 50 | -0.25 | 0.2 | 0.03 |
    pub fn preset(species: Species) -> Self {
        // Every preset ages as the model's authors' trees do (lambda from 0.65, alpha
        // from 4, adult after 14 cycles), sheds by light per internode, and stops growing
        // at its adult age.
        let d = GrowthParams {
            shed_multiplier: 0.0,
            young_apical_control: 0.65,
            vigor_multiplier: 1.2,
            young_vigor_multiplier: 1.6,
            maturity_age: 14,
            max_age: 40,
            max_shoot: 2,
            germination_light: 1.0,
            ..GrowthParams::default()
        };
        match species {
            Species::Excurrent => GrowthParams {
                apical_control: 0.62,
                young_apical_control: 0.62,
                vigor_multiplier: 0.9,
                young_vigor_multiplier: 1.3,
                branch_angle: 85.0,
                tropism: 0.05,
                droop: 0.005,
                environment_weight: 0.0,
                ..d
            },
            Species::Decurrent => GrowthParams {
                apical_control: 0.46,
                vigor_multiplier: 1.3,
                tropism: 0.05,
                environment_weight: 0.3,
                ..d
            },
            Species::Columnar => GrowthParams {
                apical_control: 0.54,
                branch_angle: 30.0,
                tropism: 0.25,
                environment_weight: 0.15,
                ..d
            },
            Species::Bush => GrowthParams {
                apical_control: 0.42,
                vigor_multiplier: 1.4,
                internode_length: 0.15,
                branch_angle: 55.0,
                tropism: 0.05,
                environment_weight: 0.3,
                ..d
            },
            Species::Weeping => GrowthParams {
                branch_angle: 50.0,
                tropism: 0.05,
                droop: 0.06,
                environment_weight: 0.15,
                ..d
            },
        }
    }

    /// [`Error::InvalidArgument`] naming the first parameter out of its range.
    pub fn validate(&self) -> Result<()> {
        use Bound::*;
        // Longest internode and thickest tip: 10,000 world units.
        const MAX_LENGTH: f32 = 1e4;
        const TIP: &str = "a radius in (0, 10000] world units (so tip_radius^pipe_exponent summed over every branch stays finite)";
        #[rustfmt::skip]
        let checks = [
            ("apical_control", self.apical_control, In(0.0, 1.0), "0..=1"),
            ("vigor_multiplier", self.vigor_multiplier, Above(0.0), "a finite number > 0"),
            ("internode_length", self.internode_length, AboveTo(0.0, MAX_LENGTH), "a length in (0, 10000] world units"),
            ("branch_angle", self.branch_angle, In(0.0, 180.0), "0..=180 degrees"),
            ("phyllotaxis", self.phyllotaxis, Any, "a finite angle"),
            ("tropism", self.tropism, In(-1.0, 1.0), "-1..=1"),
            ("environment_weight", self.environment_weight, AtLeast(0.0), "a finite number >= 0"),
            ("pipe_exponent", self.pipe_exponent, In(1.0, 4.0), "1..=4"),
            ("tip_radius", self.tip_radius, AboveTo(0.0, MAX_LENGTH), TIP),
            ("shed_multiplier", self.shed_multiplier, AtLeast(0.0), "a finite number >= 0"),
            ("shed_exponent", self.shed_exponent, In(0.0, 8.0), "0..=8"),
            ("seed_spread", self.seed_spread, AtLeast(0.0), "a finite distance factor >= 0"),
            ("perception_angle", self.perception_angle, AboveTo(0.0, 180.0), "0 < angle <= 180 degrees"),
            ("perception_reach", self.perception_reach, AboveTo(0.0, 64.0), "0 < reach <= 64 internode lengths"),
            ("occupancy_reach", self.occupancy_reach, In(0.0, 64.0), "0..=64 internode lengths"),
            ("shed_light", self.shed_light, AtLeast(0.0), "a finite light >= 0"),
            ("young_apical_control", self.young_apical_control, In(0.0, 1.0), "0..=1"),
            ("young_vigor_multiplier", self.young_vigor_multiplier, Above(0.0), "a finite number > 0"),
            ("max_height", self.max_height, AtLeast(0.0), "a finite height >= 0 world units (0: no limit)"),
            ("droop", self.droop, In(0.0, 1.0), "0..=1"),
            ("germination_light", self.germination_light, AtLeast(0.0), "a finite light >= 0"),
        ];
        for (field, v, bound, expected) in checks {
            if !(v.is_finite() && bound.holds(v)) {
                return Err(Error::invalid(field, format!("{v}; expected {expected}")));
            }
        }
        if self.maturity_age > 10_000 {
            return Err(Error::invalid(
                "maturity_age",
                format!("{}; expected 0..=10000 cycles", self.maturity_age),
            ));
        }
        if !(1..=64).contains(&self.max_shoot) {
            return Err(Error::invalid(
                "max_shoot",
                format!("{}; expected 1..=64 internodes", self.max_shoot),
            ));
        }
        Ok(())
    }
}

/// The range a parameter must lie in (besides being finite).
#[derive(Clone, Copy)]
enum Bound {
    /// Any finite value.
    Any,
    /// `lo..=hi`.
    In(f32, f32),
    /// `> lo`.
    Above(f32),
    /// `>= lo`.
    AtLeast(f32),
    /// `(lo, hi]`.
    AboveTo(f32, f32),
}

impl Bound {
    fn holds(self, v: f32) -> bool {
        match self {
            Bound::Any => true,
            Bound::In(lo, hi) => (lo..=hi).contains(&v),
            Bound::Above(lo) => v > lo,
            Bound::AtLeast(lo) => v >= lo,
            Bound::AboveTo(lo, hi) => v > lo && v <= hi,
        }
    }
}

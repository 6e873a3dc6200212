//! A species: the parameters of one tree's growth, its presets and their checks.

use crate::error::Result;

/// Longest internode and thickest tip: 10,000 world units.
const MAX_LENGTH: f32 = 1e4;
const TIP: &str = "a radius in (0, 10000] world units (so tip_radius^pipe_exponent summed over every branch stays finite)";

crate::options::options! {
/// One species: how a tree grows. `Default` is the excurrent species' values with neutral
/// apical control; start from it (or `preset`) and change the fields you need. Lengths are
/// world units, angles degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrowthParams {
    /// lambda in [0, 1]: 0.5 neutral, above favours the main axis (excurrent), below the
    /// laterals (decurrent). Default 0.5.
    pub apical_control: f32 = 0.5, checked In(0.0, 1.0), "0..=1",
    /// alpha > 0: vigour at the base = alpha * light gathered. Default 2.
    pub vigor_multiplier: f32 = 2.0, checked Above(0.0), "a finite number > 0",
    /// Length of an internode at vigour 1, in (0, 10000]. Default 0.25.
    pub internode_length: f32 = 0.25, checked AboveTo(0.0, MAX_LENGTH), "a length in (0, 10000] world units",
    /// Angle between a lateral bud and its internode's heading, 0..=180. Default 45.
    pub branch_angle: f32 = 45.0, checked In(0.0, 180.0), "0..=180 degrees",
    /// Turn about the heading from one lateral bud to the next, finite. Default 137.5.
    pub phyllotaxis: f32 = 137.5, checked Any, "a finite angle",
    /// eta: weight of up (gravitropism) in a shoot's heading; negative bends down. Finite,
    /// -1..=1. Default 0.1.
    pub tropism: f32 = 0.1, checked In(-1.0, 1.0), "-1..=1",
    /// xi >= 0: weight of the environment's optimal direction. Default 0.25.
    pub environment_weight: f32 = 0.25, checked AtLeast(0.0), "a finite number >= 0",
    /// n in [1, 4]: a parent's r^n is the sum of its children's. Default 2.5.
    pub pipe_exponent: f32 = 2.5, checked In(1.0, 4.0), "1..=4",
    /// Radius of a branch tip, in (0, 10000]. Default 0.01.
    pub tip_radius: f32 = 0.01, checked AboveTo(0.0, MAX_LENGTH), TIP,
    /// A lateral branch is shed when its vigour < shed_multiplier * internodes^shed_exponent
    /// (its internodes counted with everything above it). >= 0 (0: never). Default 0.03.
    pub shed_multiplier: f32 = 0.03, checked AtLeast(0.0), "a finite number >= 0",
    /// 0..=8. Default 1.3.
    pub shed_exponent: f32 = 1.3, checked In(0.0, 8.0), "0..=8",
    /// A branch younger than this many cycles is never shed. Default 4.
    pub shed_delay: u32 = 4,
    /// A tree older than this many cycles drops seeds each cycle; 0 (default): never.
    pub seed_age: u32 = 0,
    /// Seeds land within ln(root vigour) * seed_spread of the base, >= 0. Default 2.
    pub seed_spread: f32 = 2.0, checked AtLeast(0.0), "a finite distance factor >= 0",
    /// Space colonization: half-angle of a bud's perception cone, degrees, in (0, 180].
    /// Default 90.
    pub perception_angle: f32 = 90.0, checked AboveTo(0.0, 180.0), "0 < angle <= 180 degrees",
    /// Space colonization: reach of the perception cone, in internode lengths, in
    /// (0, 64]. Default 4.
    pub perception_reach: f32 = 4.0, checked AboveTo(0.0, 64.0), "0 < reach <= 64 internode lengths",
    /// Space colonization: markers closer than this many internode lengths to a bud are
    /// removed (occupied), 0..=64. Default 2.
    pub occupancy_reach: f32 = 2.0, checked In(0.0, 64.0), "0..=64 internode lengths",
    /// Most internodes one shoot grows in a cycle, 1..=64. Default 8.
    pub max_shoot: u32 = 8, checked In(1, 64), "1..=64 internodes",
    /// Palubicki's shedding: a lateral branch older than `shed_delay` cycles is shed when
    /// the light its buds gather, per internode it carries, is below this (a tree whose
    /// whole light per internode falls below it dies). Light is Q as the environment gives
    /// it (at most `full_light` in a shadow world, 1 with markers). >= 0 (0: off).
    /// Default 0.1. (Added after the first layout.)
    pub shed_light: f32 = 0.1, checked AtLeast(0.0), "a finite light >= 0",
    /// Apical control (lambda) of a new tree, in [0, 1]: it moves linearly to
    /// `apical_control` over `maturity_age` cycles. Default 0.5. (Added after the first
    /// layout.)
    pub young_apical_control: f32 = 0.5, checked In(0.0, 1.0), "0..=1",
    /// Vigour multiplier (alpha) of a new tree, > 0: it moves linearly to
    /// `vigor_multiplier` over `maturity_age` cycles. Default 2. (Added after the first
    /// layout.)
    pub young_vigor_multiplier: f32 = 2.0, checked Above(0.0), "a finite number > 0",
    /// Growth cycles from planting until a tree has its adult apical control and vigour
    /// multiplier, 0..=10000 (0: adult from the start). Default 0. (Added after the first
    /// layout.)
    pub maturity_age: u32 = 0, checked AtMost(10_000), "0..=10000 cycles",
    /// A tree this many cycles old grows no more shoots (it still sheds); 0: it never
    /// stops. Default 0. (Added after the first layout.)
    pub max_age: u32 = 0,
    /// No internode grows to end higher than this above the tree's base, world units,
    /// >= 0 (0: no limit). Default 0. (Added after the first layout.)
    pub max_height: f32 = 0.0, checked AtLeast(0.0), "a finite height >= 0 world units (0: no limit)",
    /// Weeping: a lateral axis's tropism falls by this for each internode of the axis
    /// before the new one, so a longer branch hangs more. 0..=1. Default 0. (Added after
    /// the first layout.)
    pub droop: f32 = 0.0, checked In(0.0, 1.0), "0..=1",
    /// In a shadow world, a seed of this species grows into a tree only where the light on
    /// the ground is at least this: full light less `shadow_strength` per bud above the
    /// ground there, at any height (buds counted over the 5 x 5 columns of cells around
    /// it, per column; see `shed_light` for the unit). >= 0. Default 0. (Added after the
    /// first layout.)
    pub germination_light: f32 = 0.0, checked AtLeast(0.0), "a finite light >= 0",
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
    /// English oak: a broad, open crown on a short trunk; 18 m (see `arbor::species`).
    Oak = 5,
    /// Norway maple: a dense, rounded crown; 15 m.
    Maple = 6,
    /// Silver birch: slender, with a narrow crown and hanging twigs; 16 m.
    Birch = 7,
    /// Weeping willow: long shoots that hang toward the ground; 12 m.
    Willow = 8,
    /// Lombardy poplar: a tall, narrow column; 22 m.
    Poplar = 9,
    /// Scots pine: a leader over wide-angled, upturned branches; 18 m.
    Pine = 10,
    /// Norway spruce: a narrow cone of whorled, drooping branches; 20 m.
    Spruce = 11,
    /// A shrub: many stems from near the ground; 2.5 m.
    Shrub = 12,
}

crate::enums::numbered!(Species as "ArborSpecies" {
    Excurrent = "excurrent",
    Decurrent = "decurrent",
    Columnar = "columnar",
    Bush = "bush",
    Weeping = "weeping",
    Oak = "oak",
    Maple = "maple",
    Birch = "birch",
    Willow = "willow",
    Poplar = "poplar",
    Pine = "pine",
    Spruce = "spruce",
    Shrub = "shrub",
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
            Species::Oak => GrowthParams {
                apical_control: 0.45,
                vigor_multiplier: 1.35,
                branch_angle: 55.0,
                tropism: 0.02,
                environment_weight: 0.35,
                droop: 0.004,
                pipe_exponent: 2.2,
                ..d
            },
            Species::Maple => GrowthParams {
                apical_control: 0.49,
                vigor_multiplier: 1.3,
                branch_angle: 42.0,
                tropism: 0.08,
                environment_weight: 0.25,
                pipe_exponent: 2.2,
                ..d
            },
            Species::Birch => GrowthParams {
                apical_control: 0.56,
                young_apical_control: 0.6,
                branch_angle: 38.0,
                tropism: 0.1,
                droop: 0.03,
                environment_weight: 0.2,
                ..d
            },
            Species::Willow => GrowthParams {
                apical_control: 0.48,
                vigor_multiplier: 1.3,
                branch_angle: 45.0,
                tropism: 0.0,
                droop: 0.16,
                environment_weight: 0.15,
                pipe_exponent: 2.2,
                ..d
            },
            Species::Poplar => GrowthParams {
                apical_control: 0.57,
                branch_angle: 24.0,
                tropism: 0.3,
                environment_weight: 0.1,
                // A stout trunk under a narrow crown of few, thin branches.
                pipe_exponent: 2.0,
                ..d
            },
            Species::Pine => GrowthParams {
                apical_control: 0.62,
                young_apical_control: 0.64,
                vigor_multiplier: 1.0,
                young_vigor_multiplier: 1.3,
                branch_angle: 80.0,
                // Limbs that turn up at their ends (a candelabra), none hanging.
                tropism: 0.06,
                droop: 0.0,
                environment_weight: 0.05,
                ..d
            },
            Species::Spruce => GrowthParams {
                apical_control: 0.63,
                young_apical_control: 0.63,
                vigor_multiplier: 0.9,
                young_vigor_multiplier: 1.3,
                branch_angle: 85.0,
                tropism: 0.03,
                droop: 0.02,
                environment_weight: 0.0,
                ..d
            },
            Species::Shrub => GrowthParams {
                apical_control: 0.4,
                vigor_multiplier: 1.4,
                internode_length: 0.15,
                branch_angle: 55.0,
                tropism: 0.05,
                environment_weight: 0.3,
                ..d
            },
        }
    }

    /// [`Error::InvalidArgument`](crate::error::Error::InvalidArgument) naming the first
    /// parameter out of its range.
    pub fn validate(&self) -> Result<()> {
        self.check_fields()
    }
}

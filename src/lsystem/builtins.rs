//! The functions a grammar's expressions may call: one table of name, arity and operation
//! that the compiler reads to compile a call and to say what it expected, and the
//! operations themselves (trigonometry in degrees, as cpfg).

/// What a call of a built-in computes (the expression compiler makes it an instruction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Call {
    F1(Func1),
    F2(Func2),
    Ran,
    Nran,
    Special(Special),
}

/// How many arguments a built-in takes, and the operation for each count.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Arity {
    One(Call),
    Two(Call),
    /// `atan(x)` or `atan(y, x)`.
    OneOrTwo(Call, Call),
}

impl Arity {
    /// The counts accepted, for messages.
    pub(crate) fn count(self) -> &'static str {
        match self {
            Arity::One(_) => "1",
            Arity::Two(_) => "2",
            Arity::OneOrTwo(..) => "1 or 2",
        }
    }
}

/// One built-in function.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Builtin {
    pub(crate) name: &'static str,
    pub(crate) arity: Arity,
}

const fn one(name: &'static str, op: Call) -> Builtin {
    Builtin {
        name,
        arity: Arity::One(op),
    }
}

const fn two(name: &'static str, op: Call) -> Builtin {
    Builtin {
        name,
        arity: Arity::Two(op),
    }
}

/// Every built-in a call may name (besides `fopen`, which takes a file's name and mode).
pub(crate) const BUILTINS: &[Builtin] = &[
    one("sin", Call::F1(Func1::Sin)),
    one("cos", Call::F1(Func1::Cos)),
    one("tan", Call::F1(Func1::Tan)),
    one("asin", Call::F1(Func1::Asin)),
    one("acos", Call::F1(Func1::Acos)),
    Builtin {
        name: "atan",
        arity: Arity::OneOrTwo(Call::F1(Func1::Atan), Call::F2(Func2::Atan2)),
    },
    two("atan2", Call::F2(Func2::Atan2)),
    one("exp", Call::F1(Func1::Exp)),
    one("log", Call::F1(Func1::Log)),
    one("sqrt", Call::F1(Func1::Sqrt)),
    one("fabs", Call::F1(Func1::Fabs)),
    one("abs", Call::F1(Func1::Fabs)),
    one("floor", Call::F1(Func1::Floor)),
    one("ceil", Call::F1(Func1::Ceil)),
    one("trunc", Call::F1(Func1::Trunc)),
    one("sign", Call::F1(Func1::Sign)),
    two("min", Call::F2(Func2::Min)),
    two("max", Call::F2(Func2::Max)),
    two("pow", Call::F2(Func2::Pow)),
    one("ran", Call::Ran),
    two("nran", Call::Nran),
    two("bran", Call::Special(Special::Bran)),
    two("biran", Call::Special(Special::Biran)),
    one("srand", Call::Special(Special::Srand)),
    two("func", Call::Special(Special::Func)),
    two("curveX", Call::Special(Special::Curve(0))),
    two("curveY", Call::Special(Special::Curve(1))),
    two("curveZ", Call::Special(Special::Curve(2))),
    one("curveGAL", Call::Special(Special::CurveLength)),
];

/// Every built-in's name, and `fopen`, for the message of an unknown call.
pub(crate) fn builtin_names() -> String {
    let mut names: Vec<&str> = BUILTINS.iter().map(|b| b.name).collect();
    names.push("fopen");
    names.join(" ")
}

/// What a cpfg function arbor does not have needs, or `None` for any other name.
pub(crate) fn unsupported(name: &str) -> Option<&'static str> {
    match name {
        "fscanf" => Some("data files read by the grammar"),
        "fclose" | "fflush" | "fprintf" => Some("a file handle used as a value"),
        "play" | "inblob" | "vvXmin" | "vvXmax" | "vvYmin" | "vvYmax" | "vvZmin" | "vvZmax"
        | "vvScale" | "Display" => Some("cpfg's viewer"),
        _ => None,
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Func1 {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Exp,
    Log,
    Sqrt,
    Fabs,
    Floor,
    Ceil,
    Trunc,
    Sign,
}

/// Functions of three or more values, and those that change the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Special {
    /// `srand(s)`: restarts the random stream; its value is 0.
    Srand,
    /// `bran(a, b)`: a draw from the beta distribution.
    Bran,
    /// `biran(n, p)`: a draw from the binomial distribution.
    Biran,
    /// `func(id, x)`: function `id` of the view file at x.
    Func,
    /// `curveX/Y/Z(id, t)`: a coordinate of curve `id` at fraction t of its length.
    Curve(u8),
    /// `curveGAL(id)`: the arc length of curve `id`.
    CurveLength,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Func2 {
    Atan2,
    Min,
    Max,
    Pow,
}

impl Func1 {
    pub(crate) fn apply(self, x: f64) -> f64 {
        match self {
            Func1::Sin => libm::sin(x.to_radians()),
            Func1::Cos => libm::cos(x.to_radians()),
            Func1::Tan => libm::tan(x.to_radians()),
            Func1::Asin => libm::asin(x).to_degrees(),
            Func1::Acos => libm::acos(x).to_degrees(),
            Func1::Atan => libm::atan(x).to_degrees(),
            Func1::Exp => libm::exp(x),
            Func1::Log => libm::log(x),
            Func1::Sqrt => x.sqrt(),
            Func1::Fabs => x.abs(),
            Func1::Floor => x.floor(),
            Func1::Ceil => x.ceil(),
            Func1::Trunc => (x + 0.5).floor(),
            Func1::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
        }
    }
}

impl Func2 {
    pub(crate) fn apply(self, x: f64, y: f64) -> f64 {
        match self {
            Func2::Atan2 => libm::atan2(x, y).to_degrees(),
            Func2::Min => x.min(y),
            Func2::Max => x.max(y),
            Func2::Pow => libm::pow(x, y),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsystem::LSystem;

    #[test]
    fn every_builtin_compiles_and_is_named_when_a_call_is_unknown() {
        let err = LSystem::parse("Axiom: F(foo(1))").unwrap_err().to_string();
        let listed: Vec<&str> = err
            .split("a function: ")
            .nth(1)
            .unwrap_or_else(|| panic!("{err}"))
            .split_whitespace()
            .collect();
        let mut names: Vec<&str> = BUILTINS.iter().map(|b| b.name).collect();
        names.push("fopen");
        assert_eq!(listed, names, "{err}");
        for b in BUILTINS {
            let args = match b.arity {
                Arity::One(_) | Arity::OneOrTwo(..) => "1",
                Arity::Two(_) => "1, 2",
            };
            let text = format!("Axiom: F({}({args}))", b.name);
            LSystem::parse(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
            let wrong = format!("Axiom: F({}(1, 2, 3))", b.name);
            let e = LSystem::parse(&wrong).unwrap_err().to_string();
            assert!(e.contains(b.arity.count()), "{wrong}: {e}");
        }
    }
}

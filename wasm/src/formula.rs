//! A visitor's own potential `U(x, y)`, typed as a formula: parsed into a
//! small postfix program and evaluated in forward mode (dual numbers), so
//! that the gradient the chains follow is exact, not a finite difference.
//!
//! The language: numbers (`2`, `0.5`, `1e-3`), the variables `x` and `y`,
//! the constants `pi` and `e`, `+ - * / ^` (also `**`; `^` binds tighter
//! than a leading minus and to the right: `-x^2^3 = -(x^(2^3))`), implicit
//! products (`2x`, `3(x + 1)`, `2 pi x`), parentheses, and the functions
//! `sin cos tan asin acos atan sinh cosh tanh exp log ln sqrt abs` (one
//! argument) and `min max` (two). `−`, `×` and `·` are read as `-`, `*`
//! and `*`. Every function is `libm`'s, as in the kernel, so a formula
//! gives the same bits on every target.
//!
//! A formula that cannot be read is a [`FormulaError`] naming the column
//! (1-based, in characters) where reading stopped.

use core::fmt;

/// The longest formula read, in characters.
pub const MAX_FORMULA_LEN: usize = 400;
/// The deepest nesting of parentheses, function calls and signs.
pub const MAX_FORMULA_DEPTH: usize = 32;
/// The most values the program holds at once while it runs: a level of
/// nesting holds at most three (a sum's left side, a product's, a power's
/// base), so no formula within [`MAX_FORMULA_DEPTH`] needs more.
const MAX_STACK: usize = 3 * (MAX_FORMULA_DEPTH + 1) + 1;

/// A number and its partial derivatives in `x` and `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Dual {
    v: f64,
    dx: f64,
    dy: f64,
}

impl Dual {
    const fn constant(v: f64) -> Self {
        Self {
            v,
            dx: 0.0,
            dy: 0.0,
        }
    }
    /// `f(self)` with `f'(self.v) = slope`.
    fn chain(self, v: f64, slope: f64) -> Self {
        Self {
            v,
            dx: slope * self.dx,
            dy: slope * self.dy,
        }
    }
}

/// The functions of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum F1 {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
    Exp,
    Log,
    Sqrt,
    Abs,
}

impl F1 {
    fn apply(self, a: Dual) -> Dual {
        let v = a.v;
        match self {
            F1::Sin => a.chain(libm::sin(v), libm::cos(v)),
            F1::Cos => a.chain(libm::cos(v), -libm::sin(v)),
            F1::Tan => {
                let t = libm::tan(v);
                a.chain(t, 1.0 + t * t)
            }
            F1::Asin => a.chain(libm::asin(v), 1.0 / libm::sqrt(1.0 - v * v)),
            F1::Acos => a.chain(libm::acos(v), -1.0 / libm::sqrt(1.0 - v * v)),
            F1::Atan => a.chain(libm::atan(v), 1.0 / (1.0 + v * v)),
            F1::Sinh => a.chain(libm::sinh(v), libm::cosh(v)),
            F1::Cosh => a.chain(libm::cosh(v), libm::sinh(v)),
            F1::Tanh => {
                let t = libm::tanh(v);
                a.chain(t, 1.0 - t * t)
            }
            F1::Exp => {
                let e = libm::exp(v);
                a.chain(e, e)
            }
            F1::Log => a.chain(libm::log(v), 1.0 / v),
            F1::Sqrt => {
                let r = libm::sqrt(v);
                a.chain(r, 0.5 / r)
            }
            F1::Abs => a.chain(libm::fabs(v), if v < 0.0 { -1.0 } else { 1.0 }),
        }
    }
}

/// One instruction of the postfix program.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Const(f64),
    X,
    Y,
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    /// `a ^ n` for a constant whole exponent: defined for negative `a`.
    PowI(i32),
    Pow,
    F1(F1),
    Min,
    Max,
}

/// The names a formula may use, with what they stand for.
const FUNCTIONS: [(&str, F1); 14] = [
    ("sin", F1::Sin),
    ("cos", F1::Cos),
    ("tan", F1::Tan),
    ("asin", F1::Asin),
    ("acos", F1::Acos),
    ("atan", F1::Atan),
    ("sinh", F1::Sinh),
    ("cosh", F1::Cosh),
    ("tanh", F1::Tanh),
    ("exp", F1::Exp),
    ("log", F1::Log),
    ("ln", F1::Log),
    ("sqrt", F1::Sqrt),
    ("abs", F1::Abs),
];

/// Why a formula could not be read, and where.
#[derive(Clone, Debug, PartialEq)]
pub struct FormulaError {
    /// The column (1-based, in characters) where reading stopped.
    pub column: usize,
    /// What was wrong there.
    pub kind: FormulaErrorKind,
}

/// What was wrong in a formula.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FormulaErrorKind {
    /// Nothing but blanks.
    Empty,
    /// Longer than [`MAX_FORMULA_LEN`] characters.
    TooLong {
        /// Its length.
        length: usize,
    },
    /// A character that is in no number, name or operator.
    Character(char),
    /// The formula ended where more was needed.
    End {
        /// What was needed.
        expected: &'static str,
    },
    /// Something else than what was needed.
    Unexpected {
        /// What was found.
        found: String,
        /// What was needed.
        expected: &'static str,
    },
    /// A name that is no variable, constant or function.
    UnknownName(String),
    /// A function given the wrong number of arguments.
    Arguments {
        /// The function.
        name: &'static str,
        /// How many it takes.
        takes: usize,
        /// How many it was given.
        given: usize,
    },
    /// A number that does not fit an f64 (`1e400`).
    Number(String),
    /// Nested deeper than [`MAX_FORMULA_DEPTH`], or needing more than the
    /// program's stack.
    TooDeep,
}

impl fmt::Display for FormulaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`formula`, column {}: ", self.column)?;
        match &self.kind {
            FormulaErrorKind::Empty => {
                f.write_str("the formula is empty: type U in x and y, such as x^2 + y^2")
            }
            FormulaErrorKind::TooLong { length } => {
                write!(
                    f,
                    "the formula has {length} characters, more than the {MAX_FORMULA_LEN} read"
                )
            }
            FormulaErrorKind::Character(c) => write!(f, "“{c}” is not part of a formula"),
            FormulaErrorKind::End { expected } => {
                write!(f, "the formula ends where {expected} is needed")
            }
            FormulaErrorKind::Unexpected { found, expected } => {
                write!(f, "“{found}” where {expected} is needed")
            }
            FormulaErrorKind::UnknownName(name) => write!(
                f,
                "“{name}” is not known: the variables are x and y, the constants pi and e, the functions {} min max",
                FUNCTIONS.map(|(n, _)| n).join(" ")
            ),
            FormulaErrorKind::Arguments { name, takes, given } => write!(
                f,
                "{name} takes {takes} argument{}, given {given}",
                if *takes == 1 { "" } else { "s" }
            ),
            FormulaErrorKind::Number(text) => write!(f, "the number {text} is too large"),
            FormulaErrorKind::TooDeep => write!(f, "nested more than {MAX_FORMULA_DEPTH} deep"),
        }
    }
}

impl core::error::Error for FormulaError {}

/// A token and the column it starts at (0-based, in characters).
#[derive(Clone, Debug, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Symbol(char),
}

fn tokens(text: &str) -> Result<Vec<(Token, usize)>, FormulaError> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(char::is_ascii_digit)) {
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent only when digits follow: `2e` is 2 times e.
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let text: String = chars[start..i].iter().collect();
            let v: f64 = text.parse().map_err(|_| FormulaError {
                column: start + 1,
                kind: FormulaErrorKind::Unexpected {
                    found: text.clone(),
                    expected: "a number",
                },
            })?;
            if !v.is_finite() {
                return Err(FormulaError {
                    column: start + 1,
                    kind: FormulaErrorKind::Number(text),
                });
            }
            out.push((Token::Number(v), start));
            continue;
        }
        if c.is_ascii_alphabetic() || c == '_' {
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Token::Name(chars[start..i].iter().collect()), start));
            continue;
        }
        let symbol = match c {
            '*' if chars.get(i + 1) == Some(&'*') => {
                i += 1;
                '^'
            }
            '+' | '-' | '*' | '/' | '^' | '(' | ')' | ',' => c,
            '−' => '-',
            '×' | '·' => '*',
            _ => {
                return Err(FormulaError {
                    column: start + 1,
                    kind: FormulaErrorKind::Character(c),
                });
            }
        };
        i += 1;
        out.push((Token::Symbol(symbol), start));
    }
    Ok(out)
}

/// The syntax tree, before it is compiled.
#[derive(Clone, Debug)]
enum Node {
    Number(f64),
    X,
    Y,
    Neg(Box<Node>),
    Binary(char, Box<Node>, Box<Node>),
    Call1(F1, Box<Node>),
    Call2(bool, Box<Node>, Box<Node>),
}

struct Parser {
    tokens: Vec<(Token, usize)>,
    at: usize,
    /// The column just past the end, for errors there.
    end: usize,
    depth: usize,
}

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.at).map(|(t, _)| t)
    }

    fn column(&self) -> usize {
        self.tokens.get(self.at).map_or(self.end, |&(_, c)| c) + 1
    }

    fn error(&self, expected: &'static str) -> FormulaError {
        let kind = match self.tokens.get(self.at) {
            None => FormulaErrorKind::End { expected },
            Some((t, _)) => FormulaErrorKind::Unexpected {
                found: match t {
                    Token::Number(v) => format!("{v}"),
                    Token::Name(n) => n.clone(),
                    Token::Symbol(s) => s.to_string(),
                },
                expected,
            },
        };
        FormulaError {
            column: self.column(),
            kind,
        }
    }

    fn eat(&mut self, symbol: char) -> bool {
        if self.peek() == Some(&Token::Symbol(symbol)) {
            self.at += 1;
            true
        } else {
            false
        }
    }

    /// One level deeper, opened by the token just read (a parenthesis, a
    /// sign, `^`): refused there beyond [`MAX_FORMULA_DEPTH`].
    fn deeper(&mut self) -> Result<(), FormulaError> {
        self.depth += 1;
        if self.depth > MAX_FORMULA_DEPTH {
            let opened = self.at.checked_sub(1).and_then(|i| self.tokens.get(i));
            return Err(FormulaError {
                column: opened.map_or(1, |&(_, c)| c + 1),
                kind: FormulaErrorKind::TooDeep,
            });
        }
        Ok(())
    }

    /// sum := product (('+' | '-') product)*
    fn sum(&mut self) -> Result<Node, FormulaError> {
        let mut left = self.product()?;
        while let Some(Token::Symbol(op @ ('+' | '-'))) = self.peek().cloned() {
            self.at += 1;
            let right = self.product()?;
            left = Node::Binary(op, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    /// product := signed (('*' | '/' | implicit) signed)*
    fn product(&mut self) -> Result<Node, FormulaError> {
        let mut left = self.signed()?;
        loop {
            let op = match self.peek() {
                Some(Token::Symbol(op @ ('*' | '/'))) => {
                    let op = *op;
                    self.at += 1;
                    op
                }
                // `2x`, `3(x + 1)`, `x y`: a product without a sign.
                Some(Token::Number(_) | Token::Name(_) | Token::Symbol('(')) => '*',
                _ => return Ok(left),
            };
            let right = self.signed()?;
            left = Node::Binary(op, Box::new(left), Box::new(right));
        }
    }

    /// signed := ('-' | '+') signed | power
    fn signed(&mut self) -> Result<Node, FormulaError> {
        if self.eat('-') {
            self.deeper()?;
            let inner = self.signed()?;
            self.depth -= 1;
            return Ok(Node::Neg(Box::new(inner)));
        }
        if self.eat('+') {
            self.deeper()?;
            let inner = self.signed()?;
            self.depth -= 1;
            return Ok(inner);
        }
        self.power()
    }

    /// power := atom ('^' signed)?, to the right.
    fn power(&mut self) -> Result<Node, FormulaError> {
        let base = self.atom()?;
        if self.eat('^') {
            self.deeper()?;
            let exponent = self.signed()?;
            self.depth -= 1;
            return Ok(Node::Binary('^', Box::new(base), Box::new(exponent)));
        }
        Ok(base)
    }

    /// atom := number | x | y | pi | e | function '(' sum (',' sum)* ')' | '(' sum ')'
    fn atom(&mut self) -> Result<Node, FormulaError> {
        const WANTED: &str = "a number, x, y, a function or “(”";
        let (token, column) = match self.tokens.get(self.at) {
            Some(t) => t.clone(),
            None => return Err(self.error(WANTED)),
        };
        match token {
            Token::Number(v) => {
                self.at += 1;
                Ok(Node::Number(v))
            }
            Token::Symbol('(') => {
                self.at += 1;
                self.deeper()?;
                let inner = self.sum()?;
                self.depth -= 1;
                if !self.eat(')') {
                    return Err(self.error("“)”"));
                }
                Ok(inner)
            }
            Token::Symbol(_) => Err(self.error(WANTED)),
            Token::Name(name) => {
                self.at += 1;
                match name.as_str() {
                    "x" => return Ok(Node::X),
                    "y" => return Ok(Node::Y),
                    "pi" => return Ok(Node::Number(core::f64::consts::PI)),
                    "e" => return Ok(Node::Number(core::f64::consts::E)),
                    _ => {}
                }
                let one = FUNCTIONS.iter().find(|(n, _)| *n == name);
                let two = ["min", "max"].into_iter().find(|&n| n == name);
                let (label, takes) = match (one, two) {
                    (Some((n, _)), _) => (*n, 1),
                    (None, Some(n)) => (n, 2),
                    (None, None) => {
                        return Err(FormulaError {
                            column: column + 1,
                            kind: FormulaErrorKind::UnknownName(name),
                        });
                    }
                };
                if !self.eat('(') {
                    return Err(self.error("“(” after a function's name"));
                }
                self.deeper()?;
                let mut args = vec![self.sum()?];
                while self.eat(',') {
                    args.push(self.sum()?);
                }
                self.depth -= 1;
                if !self.eat(')') {
                    return Err(self.error("“)” or “,”"));
                }
                if args.len() != takes {
                    return Err(FormulaError {
                        column: column + 1,
                        kind: FormulaErrorKind::Arguments {
                            name: label,
                            takes,
                            given: args.len(),
                        },
                    });
                }
                let mut args = args.into_iter().map(Box::new);
                Ok(match (one, args.next(), args.next()) {
                    (Some(&(_, f)), Some(a), None) => Node::Call1(f, a),
                    (None, Some(a), Some(b)) => Node::Call2(label == "max", a, b),
                    // The count was checked above.
                    _ => {
                        return Err(FormulaError {
                            column: column + 1,
                            kind: FormulaErrorKind::Arguments {
                                name: label,
                                takes,
                                given: takes,
                            },
                        });
                    }
                })
            }
        }
    }
}

/// A formula compiled to a postfix program over dual numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct Formula {
    text: String,
    program: Vec<Op>,
}

impl Formula {
    /// Reads `text`; see the module's documentation for the language.
    pub fn parse(text: &str) -> Result<Self, FormulaError> {
        let length = text.chars().count();
        if length > MAX_FORMULA_LEN {
            return Err(FormulaError {
                column: MAX_FORMULA_LEN + 1,
                kind: FormulaErrorKind::TooLong { length },
            });
        }
        let tokens = tokens(text)?;
        if tokens.is_empty() {
            return Err(FormulaError {
                column: 1,
                kind: FormulaErrorKind::Empty,
            });
        }
        let mut parser = Parser {
            tokens,
            at: 0,
            end: length,
            depth: 0,
        };
        let tree = parser.sum()?;
        if parser.at < parser.tokens.len() {
            return Err(parser.error("an operator or the end"));
        }
        let mut program = Vec::new();
        compile(&fold(tree), &mut program);
        if stack_needed(&program) > MAX_STACK {
            return Err(FormulaError {
                column: 1,
                kind: FormulaErrorKind::TooDeep,
            });
        }
        Ok(Self {
            text: text.into(),
            program,
        })
    }

    /// The formula as typed.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// `U(x, y)` and its exact gradient.
    pub fn value_and_gradient(&self, x: f64, y: f64) -> (f64, [f64; 2]) {
        let mut stack = [Dual::constant(0.0); MAX_STACK];
        let mut top = 0;
        // The program is postfix and its stack depth was checked when it
        // was compiled: every pop has its operands.
        let binary = |stack: &mut [Dual; MAX_STACK], top: &mut usize, f: fn(Dual, Dual) -> Dual| {
            *top -= 1;
            stack[*top - 1] = f(stack[*top - 1], stack[*top]);
        };
        // The variables, each with its own direction of the gradient.
        let (x, y) = (
            Dual {
                v: x,
                dx: 1.0,
                dy: 0.0,
            },
            Dual {
                v: y,
                dx: 0.0,
                dy: 1.0,
            },
        );
        for op in &self.program {
            match *op {
                Op::Const(v) => {
                    stack[top] = Dual::constant(v);
                    top += 1;
                }
                Op::X => {
                    stack[top] = x;
                    top += 1;
                }
                Op::Y => {
                    stack[top] = y;
                    top += 1;
                }
                Op::Neg => {
                    let a = stack[top - 1];
                    stack[top - 1] = Dual {
                        v: -a.v,
                        dx: -a.dx,
                        dy: -a.dy,
                    };
                }
                Op::F1(f) => stack[top - 1] = f.apply(stack[top - 1]),
                Op::PowI(n) => {
                    let a = stack[top - 1];
                    let n = f64::from(n);
                    stack[top - 1] = a.chain(libm::pow(a.v, n), n * libm::pow(a.v, n - 1.0));
                }
                Op::Add => binary(&mut stack, &mut top, |a, b| Dual {
                    v: a.v + b.v,
                    dx: a.dx + b.dx,
                    dy: a.dy + b.dy,
                }),
                Op::Sub => binary(&mut stack, &mut top, |a, b| Dual {
                    v: a.v - b.v,
                    dx: a.dx - b.dx,
                    dy: a.dy - b.dy,
                }),
                Op::Mul => binary(&mut stack, &mut top, |a, b| Dual {
                    v: a.v * b.v,
                    dx: a.dx * b.v + a.v * b.dx,
                    dy: a.dy * b.v + a.v * b.dy,
                }),
                Op::Div => binary(&mut stack, &mut top, |a, b| Dual {
                    v: a.v / b.v,
                    dx: (a.dx * b.v - a.v * b.dx) / (b.v * b.v),
                    dy: (a.dy * b.v - a.v * b.dy) / (b.v * b.v),
                }),
                // d(a^b) = a^b (b' ln a + b a' / a).
                Op::Pow => binary(&mut stack, &mut top, |a, b| {
                    let p = libm::pow(a.v, b.v);
                    let ln = libm::log(a.v);
                    Dual {
                        v: p,
                        dx: p * (b.dx * ln + b.v * a.dx / a.v),
                        dy: p * (b.dy * ln + b.v * a.dy / a.v),
                    }
                }),
                Op::Min => binary(&mut stack, &mut top, |a, b| if a.v <= b.v { a } else { b }),
                Op::Max => binary(&mut stack, &mut top, |a, b| if a.v >= b.v { a } else { b }),
            }
        }
        let u = stack[0];
        (u.v, [u.dx, u.dy])
    }
}

/// Folds every subtree without a variable into its value; turns `a ^ n`
/// with a whole constant `n` into the power that is defined for negative `a`.
fn fold(node: Node) -> Node {
    let constant = |n: &Node| match n {
        Node::Number(v) => Some(*v),
        _ => None,
    };
    let node = match node {
        Node::Neg(a) => Node::Neg(Box::new(fold(*a))),
        Node::Binary(op, a, b) => Node::Binary(op, Box::new(fold(*a)), Box::new(fold(*b))),
        Node::Call1(f, a) => Node::Call1(f, Box::new(fold(*a))),
        Node::Call2(max, a, b) => Node::Call2(max, Box::new(fold(*a)), Box::new(fold(*b))),
        leaf => leaf,
    };
    let value = match &node {
        Node::Neg(a) => constant(a).map(|v| -v),
        Node::Binary(op, a, b) => match (constant(a), constant(b)) {
            (Some(a), Some(b)) => Some(match op {
                '+' => a + b,
                '-' => a - b,
                '*' => a * b,
                '/' => a / b,
                _ => libm::pow(a, b),
            }),
            _ => None,
        },
        Node::Call1(f, a) => constant(a).map(|v| f.apply(Dual::constant(v)).v),
        Node::Call2(max, a, b) => match (constant(a), constant(b)) {
            (Some(a), Some(b)) => Some(if *max { a.max(b) } else { a.min(b) }),
            _ => None,
        },
        _ => None,
    };
    value.map_or(node, Node::Number)
}

fn compile(node: &Node, out: &mut Vec<Op>) {
    match node {
        Node::Number(v) => out.push(Op::Const(*v)),
        Node::X => out.push(Op::X),
        Node::Y => out.push(Op::Y),
        Node::Neg(a) => {
            compile(a, out);
            out.push(Op::Neg);
        }
        Node::Binary('^', a, b) => {
            compile(a, out);
            match **b {
                Node::Number(n) if n.fract() == 0.0 && n.abs() <= 1024.0 => {
                    out.push(Op::PowI(n as i32))
                }
                _ => {
                    compile(b, out);
                    out.push(Op::Pow);
                }
            }
        }
        Node::Binary(op, a, b) => {
            compile(a, out);
            compile(b, out);
            out.push(match op {
                '+' => Op::Add,
                '-' => Op::Sub,
                '*' => Op::Mul,
                _ => Op::Div,
            });
        }
        Node::Call1(f, a) => {
            compile(a, out);
            out.push(Op::F1(*f));
        }
        Node::Call2(max, a, b) => {
            compile(a, out);
            compile(b, out);
            out.push(if *max { Op::Max } else { Op::Min });
        }
    }
}

/// The most values the program holds at once.
fn stack_needed(program: &[Op]) -> usize {
    let (mut now, mut most) = (0_usize, 0_usize);
    for op in program {
        match op {
            Op::Const(_) | Op::X | Op::Y => now += 1,
            Op::Neg | Op::PowI(_) | Op::F1(_) => {}
            _ => now = now.saturating_sub(1),
        }
        most = most.max(now);
    }
    most
}

#[cfg(test)]
mod tests {
    use super::*;

    fn u(text: &str, x: f64, y: f64) -> (f64, [f64; 2]) {
        Formula::parse(text).unwrap().value_and_gradient(x, y)
    }

    fn column(text: &str) -> (usize, FormulaErrorKind) {
        let e = Formula::parse(text).unwrap_err();
        (e.column, e.kind)
    }

    #[test]
    fn the_usual_operators_and_functions() {
        assert_eq!(u("x^2 + y^2", 3.0, 4.0), (25.0, [6.0, 8.0]));
        assert_eq!(u("2x + 3(y - 1)", 1.0, 2.0), (5.0, [2.0, 3.0]));
        assert_eq!(u("-x^2", 3.0, 0.0).0, -9.0);
        assert_eq!(u("2^3^2", 0.0, 0.0).0, 512.0);
        assert_eq!(u("x ** 3", -2.0, 0.0), (-8.0, [12.0, 0.0]));
        assert_eq!(u("x−y×2·1", 5.0, 1.0).0, 3.0);
        assert_eq!(u("2 pi x", 1.0, 0.0).0, 2.0 * core::f64::consts::PI);
        assert_eq!(
            u("1e-3 x + 2e x", 1.0, 0.0).0,
            1e-3 + 2.0 * core::f64::consts::E
        );
        assert_eq!(u("min(x, y) + max(x, y)", 1.0, 2.0), (3.0, [1.0, 1.0]));
        assert_eq!(u("abs(x) + sqrt(y)", -2.0, 4.0), (4.0, [-1.0, 0.25]));
        // A negative base with a whole exponent is defined.
        assert_eq!(u("x^-1", -2.0, 0.0), (-0.5, [-0.25, 0.0]));
    }

    /// The gradient is exact: against a central difference of step 1e-6
    /// (error about 1e-9 of the second derivative's size), at points away
    /// from every kink.
    #[test]
    fn the_gradient_is_the_derivative() {
        let cases = [
            "2 + x^2 + y^2 - cos(2 pi x) - cos(2 pi y)",
            "-20 exp(-0.2 sqrt((x^2 + y^2)/2)) - exp((cos(2pi x) + cos(2pi y))/2) + 20 + e",
            "sin(x) cos(y) + tan(x/4) + asin(x/9) + acos(y/9) + atan(x y)",
            "sinh(x/3) + cosh(y/3) + tanh(x - y) + log(1 + x^2) + ln(2 + y^2)",
            "x^y + y^2.5 + (x^2 + 1)^(1/3) + 3/(1 + x^2 + y^2)",
        ];
        for text in cases {
            let f = Formula::parse(text).unwrap();
            for &(x, y) in &[(0.7, 1.3), (1.9, 0.4), (2.3, 2.1)] {
                let (_, g) = f.value_and_gradient(x, y);
                let d = 1e-6;
                let fx = (f.value_and_gradient(x + d, y).0 - f.value_and_gradient(x - d, y).0)
                    / (2.0 * d);
                let fy = (f.value_and_gradient(x, y + d).0 - f.value_and_gradient(x, y - d).0)
                    / (2.0 * d);
                for (exact, diff) in [(g[0], fx), (g[1], fy)] {
                    assert!(
                        (exact - diff).abs() <= 1e-6 * (1.0 + exact.abs()),
                        "{text} at ({x}, {y}): {exact} against {diff}"
                    );
                }
            }
        }
    }

    #[test]
    fn errors_point_at_the_column() {
        assert_eq!(column("x^2 + * y").0, 7);
        assert!(matches!(
            column("x^2 + * y").1,
            FormulaErrorKind::Unexpected { .. }
        ));
        assert_eq!(
            column("x^2 +"),
            (
                6,
                FormulaErrorKind::End {
                    expected: "a number, x, y, a function or “(”"
                }
            )
        );
        assert_eq!(
            column("sin(x"),
            (
                6,
                FormulaErrorKind::End {
                    expected: "“)” or “,”"
                }
            )
        );
        assert_eq!(
            column("x + z"),
            (5, FormulaErrorKind::UnknownName("z".into()))
        );
        assert_eq!(column("x + $"), (5, FormulaErrorKind::Character('$')));
        assert_eq!(column("é + x"), (1, FormulaErrorKind::Character('é')));
        // Columns count characters, not bytes.
        assert_eq!(column("−x + ?").0, 6);
        assert_eq!(column("sin x").0, 5);
        assert_eq!(
            column("max(x)"),
            (
                1,
                FormulaErrorKind::Arguments {
                    name: "max",
                    takes: 2,
                    given: 1
                }
            )
        );
        assert_eq!(
            column("2 sin(x, y)"),
            (
                3,
                FormulaErrorKind::Arguments {
                    name: "sin",
                    takes: 1,
                    given: 2
                }
            )
        );
        assert_eq!(column("(x + y))").0, 8);
        assert_eq!(column("   ").1, FormulaErrorKind::Empty);
        assert_eq!(
            column("1e400 x").1,
            FormulaErrorKind::Number("1e400".into())
        );
        assert_eq!(column(&"(".repeat(40)).1, FormulaErrorKind::TooDeep);
        assert_eq!(column(&"-".repeat(40)).1, FormulaErrorKind::TooDeep);
        assert!(matches!(
            column(&"x+".repeat(300)).1,
            FormulaErrorKind::TooLong { .. }
        ));
        assert_eq!(
            Formula::parse("x +* y").unwrap_err().to_string(),
            "`formula`, column 4: “*” where a number, x, y, a function or “(” is needed"
        );
    }

    /// Deep right-nested powers need a deep stack: refused, not a panic.
    #[test]
    fn a_program_beyond_the_stack_is_refused() {
        let mut text = String::from("x");
        for _ in 0..30 {
            text = format!("x + (x * {text})");
        }
        // 30 levels of nesting fit MAX_FORMULA_DEPTH; the stack they need fits too.
        let f = Formula::parse(&text).unwrap();
        assert!(f.value_and_gradient(0.5, 0.5).0.is_finite());
        let deep = format!("{}x{}", "(x + ".repeat(31), ")".repeat(31));
        assert!(Formula::parse(&deep).is_ok());
        // Four levels a repetition: 28 deep.
        let powers = format!("{}x{}", "(x * x ^ -(".repeat(7), "))".repeat(7));
        assert!(
            Formula::parse(&powers)
                .unwrap()
                .value_and_gradient(1.1, 0.0)
                .0
                .is_finite()
        );
    }

    #[test]
    fn constants_fold_and_undefined_points_are_not_finite() {
        let f = Formula::parse("(2 + 3) * x + sin(0)").unwrap();
        assert_eq!(
            f.program,
            vec![Op::Const(5.0), Op::X, Op::Mul, Op::Const(0.0), Op::Add]
        );
        assert!(u("log(x)", -1.0, 0.0).0.is_nan());
        assert!(u("sqrt(x)", 0.0, 0.0).1[0].is_infinite());
        assert_eq!(u("y", 1.0, 7.0), (7.0, [0.0, 1.0]));
    }
}

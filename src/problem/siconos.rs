//! Siconos numerics' text format for local friction-contact problems (`.dat`, as written by
//! `frictionContact_printInFile` and read by `frictionContact_newFromFile`):
//! docs/problem-library.md §"Siconos' .dat format".
//!
//! The file is a stream of whitespace-separated tokens (line breaks matter only inside a
//! storage-2 matrix): the dimension d (3, or 2), the number of contacts nc, the matrix W
//! (n × n, n = d·nc) as a Siconos `NumericsMatrix`, then q (n numbers) and μ (nc numbers).
//! Anything after μ is ignored, as Siconos ignores it (older files end with a flag, 0 or 1).
//! W is stored as one of
//!
//! - 0, dense: `0 n n n n` then the n² entries **column by column** (W[i][j] is entry
//!   i + j·n);
//! - 1, sparse block (block compressed rows): `1 n n nbblocks nbr nbc`, the cumulative row and
//!   column sizes of the block rows and columns, `filled1 filled2`, the block-row pointer
//!   (filled1 entries) and the block column of each block (filled2 entries), then per block its
//!   number and its d × d entries **column by column**;
//! - 2, sparse (CSparse, compressed columns or triplets, printed with 6 significant digits).
//!
//! Siconos' unknowns are ours: r = λ (normal first), u = w = W r + q, the same Coulomb law.

use super::{FrictionModel, LocalProblem};

/// A local problem read from a file whose dimension is known only after reading it.
#[derive(Clone, Debug, PartialEq)]
pub enum AnyLocalProblem {
    /// d = 3: rows n, t1, t2.
    Three(LocalProblem<3>),
    /// d = 2: rows n, t.
    Two(LocalProblem<2>),
}

impl AnyLocalProblem {
    /// Contacts in the problem.
    pub fn contacts(&self) -> usize {
        match self {
            AnyLocalProblem::Three(p) => p.contacts.len(),
            AnyLocalProblem::Two(p) => p.contacts.len(),
        }
    }
}

/// Reads the text of a Siconos `.dat` local problem. Errors say what is wrong and where (token
/// or line number); a global problem (M, H, q, b, μ) is refused as such.
pub fn parse_dat(text: &str) -> Result<AnyLocalProblem, String> {
    let mut t = Tokens::new(text);
    let d = t.integer("the dimension")?;
    let nc = t.integer("the number of contacts")?;
    match d {
        3 => read_local::<3>(&mut t, nc).map(AnyLocalProblem::Three),
        2 => read_local::<2>(&mut t, nc).map(AnyLocalProblem::Two),
        d => Err(format!(
            "dimension {d}: a friction-contact problem has 2 or 3"
        )),
    }
}

/// Reads a Siconos `.dat` local problem; errors name the file.
pub fn read_dat(path: &std::path::Path) -> Result<AnyLocalProblem, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    parse_dat(&text).map_err(|e| format!("{}: {e}", path.display()))
}

fn read_local<const R: usize>(t: &mut Tokens, nc: usize) -> Result<LocalProblem<R>, String> {
    let n = nc
        .checked_mul(R)
        .ok_or("the number of contacts is too large")?;
    let entries = read_matrix(t, n)?;
    let q = (0..n)
        .map(|i| t.number(&format!("q[{i}]")))
        .collect::<Result<Vec<f64>, String>>()?;
    let mu = (0..nc)
        .map(|i| t.number(&format!("mu[{i}]")))
        .collect::<Result<Vec<f64>, String>>()?;
    let rest = t.remaining();
    if rest > 1 {
        return Err(format!(
            "{rest} tokens after mu: this looks like a global problem (M, H, q, b, mu), which \
             is not a local problem (W, q, mu); rigidref reads local problems"
        ));
    }
    LocalProblem::from_entries(FrictionModel::Cone, entries, &q, &mu)
}

/// W's entries (row, column, value) from a NumericsMatrix of size n × n.
fn read_matrix(t: &mut Tokens, n: usize) -> Result<Vec<(usize, usize, f64)>, String> {
    let storage = t.integer("W's storage type")?;
    let rows = t.integer("W's row count")?;
    let cols = t.integer("W's column count")?;
    if rows != n || cols != n {
        return Err(format!(
            "W is {rows}×{cols}; a problem of this dimension and number of contacts has {n}×{n}"
        ));
    }
    match storage {
        0 => {
            // The sizes again (they override the first pair in Siconos' reader).
            let (r2, c2) = (t.integer("W's row count")?, t.integer("W's column count")?);
            if r2 != n || c2 != n {
                return Err(format!("W's repeated sizes {r2}×{c2} differ from {n}×{n}"));
            }
            let count = n.checked_mul(n).ok_or("W is too large")?;
            t.expect_at_least(count, "W's dense entries")?;
            let mut entries = Vec::new();
            for index in 0..count {
                let v = t.number("an entry of W")?;
                if v != 0.0 {
                    // Column-major: entry index = i + j·n.
                    entries.push((index % n, index / n, v));
                }
            }
            Ok(entries)
        }
        1 => read_block_sparse(t, n),
        2 => read_csparse(t, n),
        s => Err(format!(
            "W's storage type {s} is not known (0 dense, 1 sparse block, 2 sparse)"
        )),
    }
}

fn read_block_sparse(t: &mut Tokens, n: usize) -> Result<Vec<(usize, usize, f64)>, String> {
    let count = t.integer("the number of blocks")?;
    if count == 0 {
        return Ok(Vec::new());
    }
    let block_rows = t.integer("the number of block rows")?;
    let block_cols = t.integer("the number of block columns")?;
    t.expect_at_least(block_rows.saturating_add(block_cols), "the block sizes")?;
    let sizes = |t: &mut Tokens, m: usize, what: &str| -> Result<Vec<usize>, String> {
        let cumulative = (0..m)
            .map(|_| t.integer(what))
            .collect::<Result<Vec<usize>, String>>()?;
        // Cumulative sizes must increase to n.
        let mut previous = 0;
        for &c in &cumulative {
            if c <= previous || c > n {
                return Err(format!("{what}: cumulative sizes must increase up to {n}"));
            }
            previous = c;
        }
        if previous != n {
            return Err(format!(
                "{what}: the last cumulative size is {previous}, not {n}"
            ));
        }
        Ok(cumulative)
    };
    let row_ends = sizes(t, block_rows, "the block row sizes")?;
    let col_ends = sizes(t, block_cols, "the block column sizes")?;
    let filled1 = t.integer("filled1")?;
    let filled2 = t.integer("filled2")?;
    if filled1 == 0 || filled1 > block_rows.saturating_add(1) || filled2 != count {
        return Err(format!(
            "filled1 {filled1} and filled2 {filled2} do not fit {block_rows} block rows and \
             {count} blocks"
        ));
    }
    t.expect_at_least(filled1.saturating_add(filled2), "the block indices")?;
    let pointer = (0..filled1)
        .map(|_| t.integer("the block-row pointer"))
        .collect::<Result<Vec<usize>, String>>()?;
    let columns = (0..filled2)
        .map(|_| t.integer("a block column index"))
        .collect::<Result<Vec<usize>, String>>()?;
    if pointer[0] != 0 || pointer.windows(2).any(|w| w[1] < w[0]) || pointer[filled1 - 1] != count {
        return Err("the block-row pointer must rise from 0 to the number of blocks".into());
    }
    let start = |ends: &[usize], i: usize| if i == 0 { 0 } else { ends[i - 1] };
    let mut entries = Vec::new();
    for i in 0..filled1 - 1 {
        for (k, &j) in columns
            .iter()
            .enumerate()
            .take(pointer[i + 1])
            .skip(pointer[i])
        {
            if j >= block_cols {
                return Err(format!("block {k}: block column {j} out of range"));
            }
            let _number = t.integer("a block number")?;
            let (r0, c0) = (start(&row_ends, i), start(&col_ends, j));
            let (nr, ncol) = (row_ends[i] - r0, col_ends[j] - c0);
            t.expect_at_least(nr.saturating_mul(ncol), "a block's entries")?;
            for b in 0..ncol {
                for a in 0..nr {
                    // Column-major within the block.
                    // Kept when zero: the block is stored, and its structure with it.
                    let v = t.number("a block entry")?;
                    entries.push((r0 + a, c0 + b, v));
                }
            }
        }
    }
    Ok(entries)
}

fn read_csparse(t: &mut Tokens, n: usize) -> Result<Vec<(usize, usize, f64)>, String> {
    // Siconos' NSM_t: 1 triplet, 2 compressed columns, 3 compressed rows (4 half triplet).
    let origin = t.integer("the sparse origin")?;
    // The rest of the origin's line, the CSparse banner, then the header line.
    t.skip_line();
    t.skip_line();
    let header = t.line().ok_or("the sparse header line is missing")?;
    let words: Vec<&str> = header.split_whitespace().collect();
    let number = |s: &str| -> Result<i64, String> {
        s.trim_end_matches(',')
            .parse::<i64>()
            .map_err(|_| format!("sparse header {header:?}: {s:?} is not an integer"))
    };
    let index = |s: &str| -> Result<usize, String> {
        s.parse::<usize>()
            .ok()
            .filter(|i| *i < n)
            .ok_or_else(|| format!("sparse index {s:?} is not in 0..{n}"))
    };
    let mut entries = Vec::new();
    if words.first() == Some(&"triplet:") {
        // `triplet: M-by-N, nzmax: NZMAX nnz: NZ`, then NZ lines `i j : x`.
        if origin != 1 && origin != 4 {
            return Err(format!(
                "a triplet header with origin {origin} (1 or 4 for triplets)"
            ));
        }
        let nz = number(words.get(5).copied().unwrap_or(""))?;
        for _ in 0..nz.max(0) {
            let line = t.line().ok_or("a triplet entry is missing")?;
            let w: Vec<&str> = line.split_whitespace().collect();
            if w.len() != 4 || w[2] != ":" {
                return Err(format!("triplet entry {line:?} is not `i j : x`"));
            }
            entries.push((index(w[0])?, index(w[1])?, parse_number(w[3])?));
        }
    } else {
        // Compressed columns (origin 2) or rows (origin 3): per outer index j a line
        // `col j : locations A to B` (or `row j : …`), then B − A + 1 lines `i : x`.
        if origin != 2 && origin != 3 {
            return Err(format!(
                "a compressed header with origin {origin} (2 columns, 3 rows)"
            ));
        }
        for j in 0..n {
            let line = t.line().ok_or("a column header is missing")?;
            let w: Vec<&str> = line.split_whitespace().collect();
            if w.len() != 7 || w[2] != ":" || w[5] != "to" || w[1] != j.to_string() {
                return Err(format!(
                    "{line:?} is not `col {j} : locations A to B` (or `row {j} : …`)"
                ));
            }
            let (a, b) = (number(w[4])?, number(w[6])?);
            for _ in a..=b {
                let line = t.line().ok_or("a column entry is missing")?;
                let w: Vec<&str> = line.split_whitespace().collect();
                if w.len() != 3 || w[1] != ":" {
                    return Err(format!("column entry {line:?} is not `i : x`"));
                }
                let (i, x) = (index(w[0])?, parse_number(w[2])?);
                entries.push(if origin == 2 { (i, j, x) } else { (j, i, x) });
            }
        }
    }
    Ok(entries)
}

fn parse_number(s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .map_err(|_| format!("{s:?} is not a number"))
}

/// The file as tokens, with a line cursor for the parts where lines matter.
struct Tokens<'a> {
    text: &'a str,
    at: usize,
    count: usize,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str) -> Self {
        Tokens {
            text,
            at: 0,
            count: 0,
        }
    }

    fn next(&mut self) -> Option<&'a str> {
        let rest = &self.text[self.at..];
        let start = rest.len() - rest.trim_start().len();
        let rest = &rest[start..];
        if rest.is_empty() {
            self.at = self.text.len();
            return None;
        }
        let end = rest.find(char::is_whitespace).unwrap_or(rest.len());
        self.at += start + end;
        self.count += 1;
        Some(&rest[..end])
    }

    fn number(&mut self, what: &str) -> Result<f64, String> {
        let token = self
            .next()
            .ok_or_else(|| format!("the file ends before {what}"))?;
        token
            .parse::<f64>()
            .map_err(|_| format!("token {}: {what}: {token:?} is not a number", self.count))
    }

    fn integer(&mut self, what: &str) -> Result<usize, String> {
        let token = self
            .next()
            .ok_or_else(|| format!("the file ends before {what}"))?;
        token.parse::<usize>().map_err(|_| {
            format!(
                "token {}: {what}: {token:?} is not a non-negative integer",
                self.count
            )
        })
    }

    /// Fails unless at least `count` more tokens could follow (a bound from the bytes left, so
    /// that a header promising more numbers than the file holds is refused before allocating).
    fn expect_at_least(&self, count: usize, what: &str) -> Result<(), String> {
        let left = self.text.len() - self.at;
        if count > left.div_ceil(2) + 1 {
            return Err(format!(
                "{what}: {count} numbers announced, but only {left} bytes are left"
            ));
        }
        Ok(())
    }

    /// Tokens left (counted without consuming them).
    fn remaining(&self) -> usize {
        self.text[self.at..].split_whitespace().count()
    }

    /// The rest of the current line, consumed with its end.
    fn line(&mut self) -> Option<&'a str> {
        if self.at >= self.text.len() {
            return None;
        }
        let rest = &self.text[self.at..];
        let end = rest.find('\n').map_or(rest.len(), |i| i + 1);
        self.at += end;
        Some(rest[..end].trim_end())
    }

    fn skip_line(&mut self) {
        let _ = self.line();
    }
}

/// The problem as a Siconos `.dat` file with W in sparse-block storage (storage 1, the blocks
/// of [`LocalProblem`]'s rows), every number printed so that it reads back to the same bits.
/// Siconos reads it with `frictionContact_newFromFile`. Its law is the Coulomb cone: a
/// box-friction problem is written as it is and would be solved as a cone problem there.
pub fn write_dat<const R: usize>(problem: &LocalProblem<R>) -> String {
    use std::fmt::Write;
    let nc = problem.contacts.len();
    let n = R * nc;
    let mut s = String::new();
    let _ = writeln!(s, "{R}\n{nc}\n1\n{n}\n{n}");
    let count = problem.blocks();
    if count == 0 {
        // No contacts: a sparse-block matrix of no blocks ends at its count (Siconos reads no
        // more of it), and q and μ are empty.
        let _ = writeln!(s, "0");
        return s;
    }
    let _ = writeln!(s, "{count}\n{nc}\n{nc}");
    let cumulative: Vec<String> = (1..=nc).map(|k| (R * k).to_string()).collect();
    let _ = writeln!(s, "{}\n{}", cumulative.join("\t"), cumulative.join("\t"));
    let _ = writeln!(s, "{}\n{count}", nc + 1);
    let mut pointer = vec![0];
    for c in &problem.contacts {
        pointer.push(pointer.last().copied().unwrap_or(0) + c.row.len());
    }
    let join = |v: &mut dyn Iterator<Item = usize>| {
        v.map(|x| x.to_string()).collect::<Vec<_>>().join("\t")
    };
    let _ = writeln!(s, "{}", join(&mut pointer.iter().copied()));
    let _ = writeln!(
        s,
        "{}",
        join(
            &mut problem
                .contacts
                .iter()
                .flat_map(|c| c.row.iter().map(|(j, _)| *j))
        )
    );
    let mut number = 0;
    for c in &problem.contacts {
        for (_, block) in &c.row {
            let _ = writeln!(s, "{number}");
            number += 1;
            // Column-major.
            for b in 0..R {
                for a in 0..R {
                    let _ = writeln!(s, "{:e}", block[(a, b)]);
                }
            }
        }
    }
    let q: Vec<String> = problem
        .contacts
        .iter()
        .flat_map(|c| c.q.iter().map(|x| format!("{x:e}")))
        .collect();
    let _ = writeln!(s, "{}", q.join(" "));
    let mu: Vec<String> = problem
        .contacts
        .iter()
        .map(|c| format!("{:e}", c.mu))
        .collect();
    let _ = writeln!(s, "{}", mu.join(" "));
    s
}

//! The disassembly scan: the code reachable from the step function in an `objdump -d`
//! listing, its size, and whether a soft-float helper or an indirect branch is among it.

use crate::error::HostError;
use std::collections::{BTreeMap, BTreeSet};

/// One function of a disassembly.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Function {
    /// Bytes of code and literal pools.
    pub bytes: u32,
    /// Functions it calls or tail-calls (by symbol).
    pub calls: BTreeSet<String>,
    /// Branches through a register (`blx rN`, `bx rN` other than `bx lr`).
    pub indirect: u32,
}

/// The call graph of a GNU `objdump -d` listing (with raw instruction bytes).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CallGraph {
    /// Functions by symbol.
    pub functions: BTreeMap<String, Function>,
}

/// Symbols of soft-float helpers: the ARM EABI ones (`__aeabi_dadd`, `__aeabi_f2d`,
/// `__aeabi_i2d`, …) and the libgcc/compiler-builtins ones (`__adddf3`, `__extendsfdf2`,
/// `__fixdfsi`, `__eqsf2`, …).
pub fn is_soft_float(symbol: &str) -> bool {
    if let Some(rest) = symbol.strip_prefix("__aeabi_") {
        const FLOAT_OPS: [&str; 16] = [
            "dadd", "dsub", "drsub", "dmul", "ddiv", "dneg", "dcmp", "fadd", "fsub", "frsub",
            "fmul", "fdiv", "fneg", "fcmp", "d2", "f2",
        ];
        return FLOAT_OPS.iter().any(|op| rest.starts_with(op))
            || rest.ends_with("2d")
            || rest.ends_with("2f");
    }
    if let Some(rest) = symbol.strip_prefix("__") {
        // `__<op><df|sf>[<df|sf|si|di>]<digit>`, e.g. __adddf3, __truncdfsf2, __floatsisf.
        let core = rest.trim_end_matches(|c: char| c.is_ascii_digit());
        let is_op = |s: &str| s.chars().all(|c| c.is_ascii_lowercase());
        return is_op(core) && (core.contains("df") || core.contains("sf"));
    }
    false
}

impl CallGraph {
    /// Parses `objdump -d` output: function headers `<addr> <symbol>:` and instruction lines
    /// `<addr>:\t<hex bytes>\t<mnemonic>\t<operands>`.
    pub fn parse(listing: &str) -> Self {
        let mut graph = CallGraph::default();
        let mut current: Option<String> = None;
        for raw in listing.lines() {
            let l = raw.trim_end();
            if let Some(name) = l
                .split_once(" <")
                .filter(|(addr, rest)| {
                    !addr.is_empty()
                        && addr.chars().all(|c| c.is_ascii_hexdigit())
                        && rest.ends_with(">:")
                })
                .map(|(_, rest)| rest.trim_end_matches(">:"))
            {
                graph.functions.entry(name.to_string()).or_default();
                current = Some(name.to_string());
                continue;
            }
            let Some(func) = current.as_ref().and_then(|c| graph.functions.get_mut(c)) else {
                continue;
            };
            let mut fields = l.split('\t');
            let addr = fields.next().unwrap_or("").trim();
            if !addr.ends_with(':') {
                continue;
            }
            let bytes: String = fields.next().unwrap_or("").split_whitespace().collect();
            if bytes.is_empty() || !bytes.chars().all(|c| c.is_ascii_hexdigit()) {
                continue;
            }
            func.bytes += (bytes.len() / 2) as u32;
            let mnemonic = fields.next().unwrap_or("").trim();
            let operands = fields.next().unwrap_or("").trim();
            let branch = mnemonic.starts_with('b') || mnemonic.starts_with("cb");
            if !branch || mnemonic.starts_with("bic") || mnemonic.starts_with("bfi") {
                continue;
            }
            if let Some(target) = operands
                .split_once('<')
                .and_then(|(_, t)| t.split_once('>'))
                .map(|(t, _)| t.split('+').next().unwrap_or(t))
            {
                if current.as_deref() != Some(target) {
                    func.calls.insert(target.to_string());
                }
            } else if (mnemonic.starts_with("blx") || mnemonic.starts_with("bx"))
                && operands != "lr"
            {
                func.indirect += 1;
            }
        }
        graph
    }

    /// Every function reachable from `root` through direct calls and tail calls, `root`
    /// included. Errors: [`HostError::Disassembly`] if `root` is not in the listing.
    pub fn reachable(&self, root: &str) -> Result<BTreeSet<String>, HostError> {
        if !self.functions.contains_key(root) {
            return Err(HostError::Disassembly(format!("no function `{root}`")));
        }
        let mut seen = BTreeSet::new();
        let mut todo = vec![root.to_string()];
        while let Some(f) = todo.pop() {
            if seen.insert(f.clone())
                && let Some(func) = self.functions.get(&f)
            {
                todo.extend(func.calls.iter().filter(|c| !seen.contains(*c)).cloned());
            }
        }
        Ok(seen)
    }
}

/// What the code reachable from one function contains.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodeReport {
    /// Reachable functions.
    pub functions: BTreeSet<String>,
    /// Their bytes of code and literal pools.
    pub bytes: u32,
    /// Indirect branches among them.
    pub indirect: u32,
    /// Soft-float helpers among them.
    pub soft_float: Vec<String>,
}

impl CodeReport {
    /// Analyses the code reachable from `root`.
    pub fn new(graph: &CallGraph, root: &str) -> Result<Self, HostError> {
        let functions = graph.reachable(root)?;
        let (mut bytes, mut indirect) = (0, 0);
        for f in functions.iter().filter_map(|f| graph.functions.get(f)) {
            bytes += f.bytes;
            indirect += f.indirect;
        }
        let soft_float = functions
            .iter()
            .filter(|f| is_soft_float(f))
            .cloned()
            .collect();
        Ok(CodeReport {
            functions,
            bytes,
            indirect,
            soft_float,
        })
    }

    /// `Ok` when nothing reachable is a soft-float helper and no branch is indirect (which
    /// could reach one unseen).
    pub fn ensure_hard_float(&self) -> Result<(), HostError> {
        if !self.soft_float.is_empty() {
            return Err(HostError::Disassembly(format!(
                "soft-float helpers reachable: {}",
                self.soft_float.join(", ")
            )));
        }
        if self.indirect > 0 {
            return Err(HostError::Disassembly(format!(
                "{} indirect branches reachable: cannot prove no soft-float helper is called",
                self.indirect
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn soft_float_names() {
        for s in [
            "__aeabi_dadd",
            "__aeabi_dcmplt",
            "__aeabi_f2d",
            "__aeabi_d2f",
            "__aeabi_i2d",
            "__aeabi_ul2d",
            "__aeabi_fmul",
            "__adddf3",
            "__extendsfdf2",
            "__truncdfsf2",
            "__fixdfsi",
            "__floatsidf",
            "__unorddf2",
            "__addsf3",
        ] {
            assert!(is_soft_float(s), "{s}");
        }
        for s in [
            "__aeabi_memcpy",
            "__aeabi_uldivmod",
            "__aeabi_memclr4",
            "purcell_mcu_step",
            "__udivdi3",
            "memset",
            "sinf",
        ] {
            assert!(!is_soft_float(s), "{s}");
        }
    }

    const LISTING: &str = "
elf:     file format elf32-littlearm

Disassembly of section .text:

00000400 <root>:
     400:\tb580      \tpush\t{r7, lr}
     402:\tf000 f803 \tbl\t40c <helper>
     406:\td001      \tbeq.n\t40a <root+0xa>
     408:\te008      \tb.n\t41c <tail>
     40a:\tbd80      \tpop\t{r7, pc}

0000040c <helper>:
     40c:\tf000 f808 \tbl\t420 <__aeabi_dmul>
     410:\t4770      \tbx\tlr
     412:\tbf00      \tnop
     414:\t3f800000 \t.word\t0x3f800000

0000041c <tail>:
     41c:\t4770      \tbx\tlr
     41e:\tbf00      \tnop

00000420 <__aeabi_dmul>:
     420:\t4770      \tbx\tlr

00000422 <unrelated>:
     422:\t4798      \tblx\tr3
     424:\tf7ff fffc \tbl\t420 <__aeabi_dmul>
";

    #[test]
    fn call_graph_finds_reachable_helpers_and_sizes() {
        let g = CallGraph::parse(LISTING);
        assert_eq!(g.functions.len(), 5);
        assert_eq!(g.functions["root"].bytes, 12);
        assert_eq!(g.functions["helper"].bytes, 12);
        assert_eq!(g.functions["unrelated"].indirect, 1);
        let r = CodeReport::new(&g, "root").unwrap();
        let names: Vec<&str> = r.functions.iter().map(String::as_str).collect();
        assert_eq!(names, ["__aeabi_dmul", "helper", "root", "tail"]);
        assert_eq!(r.bytes, 12 + 12 + 4 + 2);
        assert_eq!(r.indirect, 0);
        assert_eq!(r.soft_float, ["__aeabi_dmul"]);
        assert!(r.ensure_hard_float().is_err());
        let t = CodeReport::new(&g, "tail").unwrap();
        t.ensure_hard_float().unwrap();
        assert!(
            CodeReport::new(&g, "unrelated")
                .unwrap()
                .ensure_hard_float()
                .is_err()
        );
        assert!(matches!(
            CodeReport::new(&g, "missing"),
            Err(HostError::Disassembly(_))
        ));
    }
}

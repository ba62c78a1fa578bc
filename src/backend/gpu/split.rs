//! Arrays larger than one storage binding (lavapipe allows 128 MiB; a
//! buffer may be up to `max_buffer_size`, 2 GiB there). Such a buffer is
//! bound as several *windows*: consecutive sub-ranges of
//! [`window_bytes`] bytes (a power of two, so every window offset is a
//! multiple of `min_storage_buffer_offset_alignment`), each its own
//! binding. A kernel reaches the whole array through accessors declared
//! next to the binding, one line each:
//!
//! ```wgsl
//! @group(0) @binding(1) var<storage, read> src: array<f32>;
//! fn src_load(i: u32) -> f32 { return src[i]; }
//! ```
//!
//! (`NAME_store(i, v)` for writes). Unsplit, the accessors compile as
//! written; split into `k` windows, [`split_source`] declares the windows
//! `1 .. k` as extra bindings after the kernel's own (in the order of the
//! split bindings) and rewrites the accessors to pick the window from the
//! high bits of the index. Strided kernels (the column passes of the FFT)
//! thus keep their indexing; nothing changes for a buffer that fits.

/// Bytes of one window for a device whose largest storage binding is
/// `max_binding` and whose storage offsets align to `align`: the largest
/// power of two not above `max_binding` (at least `align`).
pub fn window_bytes(max_binding: u64, align: u64) -> u64 {
    let w = if max_binding == 0 {
        1
    } else {
        1u64 << (63 - max_binding.leading_zeros())
    };
    w.max(align.max(4).next_power_of_two())
}

/// Windows of a buffer of `size` bytes.
pub fn windows(size: u64, window: u64) -> u64 {
    size.div_ceil(window).max(1)
}

/// One storage binding as declared in a shader.
struct Decl {
    line: usize,
    access: String,
    name: String,
    ty: String,
}

fn element_bytes(ty: &str) -> Option<u64> {
    match ty {
        "f32" | "u32" | "i32" => Some(4),
        "vec2<f32>" | "vec2<u32>" | "vec2<i32>" => Some(8),
        "vec4<f32>" | "vec4<u32>" | "vec4<i32>" => Some(16),
        _ => None,
    }
}

fn find_decl(lines: &[String], binding: usize) -> Result<Decl, String> {
    let prefix = format!("@group(0) @binding({binding}) var<storage, ");
    let (line, rest) = lines
        .iter()
        .enumerate()
        .find_map(|(k, l)| l.strip_prefix(&prefix).map(|r| (k, r)))
        .ok_or_else(|| format!("no storage binding {binding}"))?;
    let (access, rest) = rest
        .split_once("> ")
        .ok_or_else(|| format!("binding {binding}: cannot parse '{}'", lines[line]))?;
    let (name, rest) = rest
        .split_once(": array<")
        .ok_or_else(|| format!("binding {binding}: not a runtime array"))?;
    let ty = rest
        .strip_suffix(">;")
        .ok_or_else(|| format!("binding {binding}: cannot parse '{}'", lines[line]))?;
    Ok(Decl {
        line,
        access: access.to_string(),
        name: name.to_string(),
        ty: ty.to_string(),
    })
}

/// `source` with storage binding `b + 1` spread over `counts[b]` windows of
/// `window` bytes (count 1: unchanged). Window `w > 0` of the `k`-th split
/// binding is a new binding numbered after the kernel's `counts.len()`
/// storage bindings, in binding order, then window order (the engine binds
/// in the same order). Every split binding must declare `NAME_load` and/or
/// `NAME_store` accessors (one line each) and be reached only through them.
pub fn split_source(source: &str, counts: &[u64], window: u64) -> Result<String, String> {
    let mut lines: Vec<String> = source.lines().map(str::to_string).collect();
    let mut next = counts.len() + 1;
    for (b, &count) in counts.iter().enumerate() {
        if count <= 1 {
            continue;
        }
        let d = find_decl(&lines, b + 1)?;
        let elem = element_bytes(&d.ty).ok_or_else(|| format!("{}: element {}", d.name, d.ty))?;
        if window % elem != 0 || window < elem {
            return Err(format!("{}: window of {window} bytes", d.name));
        }
        let shift = (window / elem).trailing_zeros();
        let mask = (window / elem - 1) as u32;
        let names: Vec<String> = (1..count).map(|w| format!("{}_w{w}", d.name)).collect();
        let mut decls = lines[d.line].clone();
        for n in &names {
            decls.push_str(&format!(
                "\n@group(0) @binding({next}) var<storage, {}> {n}: array<{}>;",
                d.access, d.ty
            ));
            next += 1;
        }
        lines[d.line] = decls;
        let head = |n: &str| {
            format!("    let split_w = {n} >> {shift}u;\n    let split_o = {n} & {mask}u;\n")
        };
        let mut found = false;
        for l in lines.iter_mut() {
            let t = l.trim_start();
            if t.starts_with(&format!("fn {}_load(", d.name)) {
                let mut f = format!("fn {}_load(i: u32) -> {} {{\n{}", d.name, d.ty, head("i"));
                for (w, n) in names.iter().enumerate() {
                    f.push_str(&format!(
                        "    if (split_w == {}u) {{ return {n}[split_o]; }}\n",
                        w + 1
                    ));
                }
                f.push_str(&format!("    return {}[split_o];\n}}", d.name));
                *l = f;
                found = true;
            } else if t.starts_with(&format!("fn {}_store(", d.name)) {
                let mut f = format!("fn {}_store(i: u32, v: {}) {{\n{}", d.name, d.ty, head("i"));
                for (w, n) in names.iter().enumerate() {
                    f.push_str(&format!(
                        "    if (split_w == {}u) {{ {n}[split_o] = v; return; }}\n",
                        w + 1
                    ));
                }
                f.push_str(&format!("    {}[split_o] = v;\n}}", d.name));
                *l = f;
                found = true;
            }
        }
        if !found {
            return Err(format!("{}: no {0}_load or {0}_store accessor", d.name));
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_are_powers_of_two_within_the_limit() {
        assert_eq!(window_bytes(128 << 20, 256), 128 << 20);
        assert_eq!(window_bytes((1 << 31) - 1, 256), 1 << 30);
        assert_eq!(window_bytes(100, 256), 256);
        assert_eq!(windows(0, 256), 1);
        assert_eq!(windows(256, 256), 1);
        assert_eq!(windows(257, 256), 2);
    }

    #[test]
    fn split_accessors_pick_the_window() {
        let src = "@group(0) @binding(1) var<storage, read> x: array<f32>;\n\
                   fn x_load(i: u32) -> f32 { return x[i]; }\n\
                   @group(0) @binding(2) var<storage, read_write> y: array<vec2<f32>>;\n\
                   fn y_store(i: u32, v: vec2<f32>) { y[i] = v; }\n";
        assert_eq!(split_source(src, &[1, 1], 1024).unwrap(), src);
        let s = split_source(src, &[3, 2], 1024).unwrap();
        assert!(s.contains("@group(0) @binding(3) var<storage, read> x_w1: array<f32>;"));
        assert!(s.contains("@group(0) @binding(4) var<storage, read> x_w2: array<f32>;"));
        assert!(s.contains("@group(0) @binding(5) var<storage, read_write> y_w1"));
        assert!(s.contains("let split_w = i >> 8u;"), "{s}");
        assert!(s.contains("let split_w = i >> 7u;"), "{s}");
        assert!(
            s.contains("if (split_w == 2u) { return x_w2[split_o]; }"),
            "{s}"
        );
        assert!(
            s.contains("if (split_w == 1u) { y_w1[split_o] = v; return; }"),
            "{s}"
        );
        assert!(split_source(src, &[1, 1, 2], 1024).is_err());
    }
}

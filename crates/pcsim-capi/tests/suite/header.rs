//! `include/pcsim.h` against the library's Rust signatures: every `extern "C"` function of
//! `src/lib.rs` is declared in the header with the same name, C return type and parameter types
//! (in order), and every `PCSIM_*` constant has the same value. The two cannot drift apart.

use std::collections::BTreeMap;

/// The C spelling of a Rust FFI type.
fn c_type(rust: &str) -> String {
    let t = rust.trim();
    let t = t.replace("std::ffi::", "");
    match t.as_str() {
        "c_int" => "int".into(),
        "f64" => "double".into(),
        "usize" => "size_t".into(),
        "*const c_char" => "const char *".into(),
        "*mut c_char" => "char *".into(),
        "*mut PcsimRt" => "PcsimRt *".into(),
        "*const PcsimRt" => "const PcsimRt *".into(),
        "*mut f64" => "double *".into(),
        "*mut u8" => "uint8_t *".into(),
        "*const u8" => "const uint8_t *".into(),
        "*mut usize" => "size_t *".into(),
        "" | "()" => "void".into(),
        other => panic!("no C spelling for Rust type `{other}`"),
    }
}

/// Normalise a C type: single spaces, `*` attached to the type.
fn norm(c: &str) -> String {
    let c = c.replace('*', " * ");
    let w: Vec<&str> = c.split_whitespace().collect();
    w.join(" ").replace("* ", "*").replace(" *", "*")
}

/// (name → (return type, parameter types)) from the Rust source.
fn rust_signatures(src: &str) -> BTreeMap<String, (String, Vec<String>)> {
    let mut out = BTreeMap::new();
    let mut rest = src;
    while let Some(i) = rest.find("extern \"C\" fn ") {
        rest = &rest[i + "extern \"C\" fn ".len()..];
        let name_end = rest.find('(').unwrap();
        let name = rest[..name_end].trim().to_string();
        let close = rest.find(')').unwrap();
        let params: Vec<String> = rest[name_end + 1..close]
            .split(',')
            .map(str::trim)
            .filter(|p| !p.is_empty())
            .map(|p| c_type(p.split_once(':').unwrap().1))
            .collect();
        let after = &rest[close + 1..];
        let body = after.find('{').unwrap();
        let ret = after[..body].trim().trim_start_matches("->").trim();
        out.insert(name, (c_type(ret), params));
    }
    out
}

/// The same from the header's prototypes.
fn c_signatures(h: &str) -> BTreeMap<String, (String, Vec<String>)> {
    let mut out = BTreeMap::new();
    for line in h.lines() {
        let l = line.trim();
        if l.starts_with('#') || l.starts_with("/*") || l.starts_with('*') || !l.ends_with(");") {
            continue;
        }
        let open = l.find('(').unwrap();
        let head = &l[..open];
        let name_start = head.rfind([' ', '*']).unwrap() + 1;
        let name = head[name_start..].to_string();
        let ret = norm(&head[..name_start]);
        let params: Vec<String> = l[open + 1..l.len() - 2]
            .split(',')
            .map(str::trim)
            .filter(|p| !p.is_empty() && *p != "void")
            .map(|p| {
                // Drop the parameter's name (the last identifier).
                let cut = p.rfind([' ', '*']).unwrap() + 1;
                norm(&p[..cut])
            })
            .collect();
        out.insert(name, (ret, params));
    }
    out
}

#[test]
fn the_header_declares_every_function_with_the_rust_signature() {
    let src = include_str!("../../src/lib.rs");
    let header = include_str!("../../../../include/pcsim.h");
    let rust: BTreeMap<_, _> = rust_signatures(src)
        .into_iter()
        .map(|(k, (r, p))| (k, (norm(&r), p.iter().map(|x| norm(x)).collect::<Vec<_>>())))
        .collect();
    let c = c_signatures(header);
    assert!(rust.len() >= 9, "{rust:?}");
    assert_eq!(
        rust.keys().collect::<Vec<_>>(),
        c.keys().collect::<Vec<_>>(),
        "functions in the library and in the header differ"
    );
    for (name, sig) in &rust {
        assert_eq!(sig, &c[name], "{name}: Rust {sig:?}, header {:?}", c[name]);
    }
    // A changed parameter is caught.
    let mut broken = c.clone();
    broken.get_mut("pcsim_rt_step").unwrap().1[1] = "float".into();
    assert_ne!(broken["pcsim_rt_step"], rust["pcsim_rt_step"]);
}

#[test]
fn the_header_constants_have_the_library_values() {
    let header = include_str!("../../../../include/pcsim.h");
    let consts = [
        ("PCSIM_OK", pcsim_capi::PCSIM_OK),
        ("PCSIM_ERR_ARGUMENT", pcsim_capi::PCSIM_ERR_ARGUMENT),
        ("PCSIM_ERR_CASE", pcsim_capi::PCSIM_ERR_CASE),
        ("PCSIM_ERR_INPUT", pcsim_capi::PCSIM_ERR_INPUT),
        ("PCSIM_ERR_STATE", pcsim_capi::PCSIM_ERR_STATE),
        ("PCSIM_ERR_INTERNAL", pcsim_capi::PCSIM_ERR_INTERNAL),
    ];
    for (name, v) in consts {
        let line = header
            .lines()
            .find(|l| l.starts_with(&format!("#define {name} ")))
            .unwrap_or_else(|| panic!("{name} is not in the header"));
        let value: i32 = line.split_whitespace().nth(2).unwrap().parse().unwrap();
        assert_eq!(value, v, "{name}");
    }
}

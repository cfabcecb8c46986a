//! The binaries are static-pie where the C library allows it (x86-64 Linux with glibc;
//! `.cargo/config.toml`, docs/DESIGN.md, "Static binaries"): linked static, so that a
//! stage starts without the dynamic loader and shared libraries, and position-independent,
//! so that address-space layout randomisation still places the program, which parses
//! untrusted scene files, at a random address. `file` calls such a binary "static-pie
//! linked"; the test reads the same from its ELF headers.
#![cfg(all(target_os = "linux", target_env = "gnu", target_arch = "x86_64"))]

use pipeline_tests::bin;
use render::fresh::binaries;

/// ELF's e_type of a position-independent executable (or shared object), and of one
/// linked to load at a fixed address.
const ET_DYN: u16 = 3;
const ET_EXEC: u16 = 2;
/// Program header types: the dynamic section (a static-pie relocates itself with it) and
/// the request for a program interpreter (the dynamic loader).
const PT_DYNAMIC: u32 = 2;
const PT_INTERP: u32 = 3;

/// A 64-bit little-endian ELF file's e_type and its program headers' types.
fn elf_kind(bytes: &[u8]) -> Result<(u16, Vec<u32>), String> {
    let u16_at = |at: usize| {
        bytes
            .get(at..at + 2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
    };
    let u32_at = |at: usize| {
        bytes
            .get(at..at + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let u64_at = |at: usize| {
        bytes
            .get(at..at + 8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
    };
    // e_ident: the magic, ELFCLASS64 (2), ELFDATA2LSB (1).
    if bytes.get(..6) != Some(&[0x7f, b'E', b'L', b'F', 2, 1][..]) {
        return Err("not a 64-bit little-endian ELF file".into());
    }
    let short = || "ELF headers cut short".to_string();
    let e_type = u16_at(16).ok_or_else(short)?;
    let phoff = u64_at(32).ok_or_else(short)? as usize;
    let phentsize = u16_at(54).ok_or_else(short)? as usize;
    let phnum = u16_at(56).ok_or_else(short)? as usize;
    let types = (0..phnum)
        .map(|i| u32_at(phoff + i * phentsize).ok_or_else(short))
        .collect::<Result<Vec<u32>, String>>()?;
    Ok((e_type, types))
}

#[test]
fn every_binary_render_builds_is_static_pie() {
    for name in binaries() {
        let path = bin(name);
        let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (e_type, headers) = elf_kind(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_ne!(
            e_type, ET_EXEC,
            "{name}: linked at a fixed address (non-PIE), out of reach of ASLR"
        );
        assert_eq!(e_type, ET_DYN, "{name}: e_type {e_type}");
        assert!(
            !headers.contains(&PT_INTERP),
            "{name}: asks for the dynamic loader (PT_INTERP): not linked static"
        );
        assert!(
            headers.contains(&PT_DYNAMIC),
            "{name}: position-independent and static, but no dynamic section to relocate \
             itself with"
        );
    }
}

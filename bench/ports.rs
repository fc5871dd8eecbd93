//! How many floating-point loads, stores and multiply-adds one x86-64 core runs per cycle: blocks
//! of eight independent instructions in an `asm!` loop, best of 7 runs of 2·10⁷ iterations.
//! `docs/performance.md` ("One vector store per cycle") has this Zen 3's figures and "What bounds
//! the cells below 20×" the Zen 4's; they say which port bounds a generated body (count its
//! instructions of each kind with `objdump`). The multiplication lines write their destinations
//! without reading them, so that the eight are independent: how many multiplication-class
//! instructions (multiplications and multiply-adds share those units) start per cycle, for
//! scalars, 256-bit and 512-bit registers (the 512-bit lines need AVX-512).
//!
//! ```sh
//! rustc -O --edition 2021 bench/ports.rs -o /tmp/ports && /tmp/ports
//! ```
//!
//! With `--clock` it prints the first line only; `bench/run.sh` and `bench/unseen.sh` record it
//! before and after their runs (`bench/clock.sh`), since this shared host's clock moves the
//! ratios between runs.
//!
//! The first line calibrates: eight multiply-add chains, one step each per iteration, take one
//! multiply-add latency per iteration (4 cycles on Zen 3), which gives the clock. The chains run
//! through `xmm0`–`xmm7` from one iteration to the next: the loop around the `asm!` does no
//! floating-point work, so nothing else writes those registers (their values are garbage; only
//! the dependency counts).
//!
//! The last two lines time straight-line code instead of a loop (the generated bodies are
//! straight-line code): a body of 12.5 KB and one of 62.5 KB. Above the 32 KB instruction
//! cache the second runs at the rate its bytes are fetched (`fetch:`, about 55 bytes/ns on the
//! Zen 4 of `docs/performance.md`'s thirty-sixth section, against 70–90 below it).

#[cfg(target_arch = "x86_64")]
fn main() {
    use std::arch::asm;
    use std::time::Instant;
    macro_rules! block {
        ($body:expr) => {{
            let mut buf = [0.0f64; 128];
            let p = buf.as_mut_ptr();
            let iters = 20_000_000u64;
            let mut best = f64::MAX;
            for _ in 0..7 {
                let t = Instant::now();
                for _ in 0..iters {
                    // SAFETY: the block reads and writes `buf` (1 KB) through `rdi` and clobbers
                    // the registers it names.
                    unsafe {
                        asm!($body, in("rdi") p, out("rax") _,
                             out("xmm0") _, out("xmm1") _, out("xmm2") _, out("xmm3") _,
                             out("xmm4") _, out("xmm5") _, out("xmm6") _, out("xmm7") _,
                             out("xmm8") _, out("xmm9") _, out("xmm10") _, out("xmm11") _,
                             options(nostack));
                    }
                }
                best = best.min(t.elapsed().as_nanos() as f64 / iters as f64);
            }
            std::hint::black_box(&buf);
            best
        }};
    }
    let calibration = block!(
        "vfmadd231sd xmm0, xmm8, xmm9\nvfmadd231sd xmm1, xmm8, xmm9\n\
         vfmadd231sd xmm2, xmm8, xmm9\nvfmadd231sd xmm3, xmm8, xmm9\n\
         vfmadd231sd xmm4, xmm8, xmm9\nvfmadd231sd xmm5, xmm8, xmm9\n\
         vfmadd231sd xmm6, xmm8, xmm9\nvfmadd231sd xmm7, xmm8, xmm9"
    );
    let cycle = calibration / 4.0;
    println!(
        "clock: {:.2} GHz (8 multiply-add chains: {calibration:.3} ns = 4 cycles)",
        1.0 / cycle
    );
    // `--clock`: the first line only (the benchmark scripts record it beside their tables).
    if std::env::args().any(|a| a == "--clock") {
        return;
    }
    let report =
        |name: &str, ns: f64| println!("{name:<44} {ns:6.3} ns  {:5.1} cycles", ns / cycle);
    report(
        "8 f64 loads (vmovsd)",
        block!(
            "vmovsd xmm0, [rdi]\nvmovsd xmm1, [rdi+8]\n\
        vmovsd xmm2, [rdi+16]\nvmovsd xmm3, [rdi+24]\nvmovsd xmm4, [rdi+32]\n\
        vmovsd xmm5, [rdi+40]\nvmovsd xmm6, [rdi+48]\nvmovsd xmm7, [rdi+56]"
        ),
    );
    report(
        "8 f64 stores (vmovsd), one cache line",
        block!(
            "vmovsd [rdi+64], xmm8\n\
        vmovsd [rdi+72], xmm9\nvmovsd [rdi+80], xmm10\nvmovsd [rdi+88], xmm11\n\
        vmovsd [rdi+96], xmm8\nvmovsd [rdi+104], xmm9\nvmovsd [rdi+112], xmm10\n\
        vmovsd [rdi+120], xmm11"
        ),
    );
    report(
        "8 f64 stores (vmovsd), eight cache lines",
        block!(
            "vmovsd [rdi], xmm8\n\
        vmovsd [rdi+64], xmm9\nvmovsd [rdi+128], xmm10\nvmovsd [rdi+192], xmm11\n\
        vmovsd [rdi+256], xmm8\nvmovsd [rdi+320], xmm9\nvmovsd [rdi+384], xmm10\n\
        vmovsd [rdi+448], xmm11"
        ),
    );
    report(
        "8 16-byte stores (vmovupd xmm)",
        block!(
            "vmovupd [rdi], xmm8\n\
        vmovupd [rdi+16], xmm9\nvmovupd [rdi+32], xmm10\nvmovupd [rdi+48], xmm11\n\
        vmovupd [rdi+64], xmm8\nvmovupd [rdi+80], xmm9\nvmovupd [rdi+96], xmm10\n\
        vmovupd [rdi+112], xmm11"
        ),
    );
    report(
        "8 32-byte stores (vmovupd ymm)",
        block!(
            "vmovupd [rdi], ymm8\n\
        vmovupd [rdi+32], ymm9\nvmovupd [rdi+64], ymm10\nvmovupd [rdi+96], ymm11\n\
        vmovupd [rdi+128], ymm8\nvmovupd [rdi+160], ymm9\nvmovupd [rdi+192], ymm10\n\
        vmovupd [rdi+224], ymm11"
        ),
    );
    report(
        "8 vmovq to a general register",
        block!(
            "vmovq rax, xmm8\nvmovq rax, xmm9\n\
        vmovq rax, xmm10\nvmovq rax, xmm11\nvmovq rax, xmm8\nvmovq rax, xmm9\n\
        vmovq rax, xmm10\nvmovq rax, xmm11"
        ),
    );
    report(
        "8 integer stores (mov)",
        block!(
            "mov [rdi], rax\nmov [rdi+8], rax\n\
        mov [rdi+16], rax\nmov [rdi+24], rax\nmov [rdi+32], rax\nmov [rdi+40], rax\n\
        mov [rdi+48], rax\nmov [rdi+56], rax"
        ),
    );
    report(
        "8 f64 multiplications (vmulsd)",
        block!(
            "vmulsd xmm0, xmm8, xmm9\nvmulsd xmm1, xmm8, xmm9\n\
        vmulsd xmm2, xmm8, xmm9\nvmulsd xmm3, xmm8, xmm9\nvmulsd xmm4, xmm8, xmm9\n\
        vmulsd xmm5, xmm8, xmm9\nvmulsd xmm6, xmm8, xmm9\nvmulsd xmm7, xmm8, xmm9"
        ),
    );
    report(
        "8 f64 multiplications and 8 additions",
        block!(
            "vmulsd xmm0, xmm8, xmm9\nvaddsd xmm4, xmm10, xmm11\n\
        vmulsd xmm1, xmm8, xmm9\nvaddsd xmm5, xmm10, xmm11\n\
        vmulsd xmm2, xmm8, xmm9\nvaddsd xmm6, xmm10, xmm11\n\
        vmulsd xmm3, xmm8, xmm9\nvaddsd xmm7, xmm10, xmm11\n\
        vmulsd xmm0, xmm9, xmm8\nvaddsd xmm4, xmm11, xmm10\n\
        vmulsd xmm1, xmm9, xmm8\nvaddsd xmm5, xmm11, xmm10\n\
        vmulsd xmm2, xmm9, xmm8\nvaddsd xmm6, xmm11, xmm10\n\
        vmulsd xmm3, xmm9, xmm8\nvaddsd xmm7, xmm11, xmm10"
        ),
    );
    report(
        "8 256-bit multiplications (vmulpd ymm)",
        block!(
            "vmulpd ymm0, ymm8, ymm9\nvmulpd ymm1, ymm8, ymm9\n\
        vmulpd ymm2, ymm8, ymm9\nvmulpd ymm3, ymm8, ymm9\nvmulpd ymm4, ymm8, ymm9\n\
        vmulpd ymm5, ymm8, ymm9\nvmulpd ymm6, ymm8, ymm9\nvmulpd ymm7, ymm8, ymm9"
        ),
    );
    if std::arch::is_x86_feature_detected!("avx512f") {
        report(
            "8 512-bit multiplications (vmulpd zmm)",
            block!(
                "vmulpd zmm0, zmm8, zmm9\nvmulpd zmm1, zmm8, zmm9\n\
            vmulpd zmm2, zmm8, zmm9\nvmulpd zmm3, zmm8, zmm9\nvmulpd zmm4, zmm8, zmm9\n\
            vmulpd zmm5, zmm8, zmm9\nvmulpd zmm6, zmm8, zmm9\nvmulpd zmm7, zmm8, zmm9"
            ),
        );
    }
    report(
        "8 f64 loads and 4 f64 stores",
        block!(
            "vmovsd xmm0, [rdi]\nvmovsd xmm1, [rdi+8]\n\
        vmovsd xmm2, [rdi+16]\nvmovsd xmm3, [rdi+24]\nvmovsd xmm4, [rdi+32]\n\
        vmovsd xmm5, [rdi+40]\nvmovsd xmm6, [rdi+48]\nvmovsd xmm7, [rdi+56]\n\
        vmovsd [rdi+64], xmm8\nvmovsd [rdi+72], xmm9\nvmovsd [rdi+80], xmm10\n\
        vmovsd [rdi+88], xmm11"
        ),
    );
    // Straight-line code, not a loop: a block of the generated bodies' kind (a load with a
    // 32-bit displacement, a multiplication, a zero idiom, a load: 25 bytes, four independent
    // instructions), repeated to a body smaller and one larger than a 32 KB instruction cache.
    // The `fetch:` line is the rate beyond it, which `bench/floors.sh` reads: a body that large
    // cannot run faster than its bytes arrive.
    macro_rules! straight {
        ($reps:literal) => {{
            let buf = [0.0f64; 1024];
            let p = buf.as_ptr();
            let iters = 20_000u64;
            let (mut best, mut bytes) = (f64::MAX, 0usize);
            for _ in 0..7 {
                let t = Instant::now();
                for _ in 0..iters {
                    // SAFETY: the block reads `buf` (8 KB) through `rdi` and clobbers the
                    // registers it names; the two `lea`s measure its length.
                    unsafe {
                        asm!("2:", concat!(".rept ", $reps),
                             "vmovsd xmm1, qword ptr [rdi + 0x800]", "vmulsd xmm2, xmm8, xmm9",
                             "vxorps xmm3, xmm3, xmm3", "vmovsd xmm4, qword ptr [rdi + 0x1000]",
                             ".endr", "3:", "lea {n}, [rip + 3b]", "lea {m}, [rip + 2b]",
                             "sub {n}, {m}", n = out(reg) bytes, m = out(reg) _, in("rdi") p,
                             out("xmm1") _, out("xmm2") _, out("xmm3") _, out("xmm4") _,
                             out("xmm8") _, out("xmm9") _, options(nostack, readonly));
                    }
                }
                best = best.min(t.elapsed().as_nanos() as f64 / iters as f64);
            }
            (bytes, best)
        }};
    }
    let (small, t_small) = straight!("500");
    println!(
        "straight-line code of {small} bytes: {:.1} bytes/ns ({:.1} ns)",
        small as f64 / t_small,
        t_small
    );
    let (large, t_large) = straight!("2500");
    println!(
        "fetch: {:.1} bytes/ns (straight-line code of {large} bytes, beyond a 32 KB instruction cache: {:.1} ns)",
        large as f64 / t_large,
        t_large
    );
}

#[cfg(not(target_arch = "x86_64"))]
fn main() {
    eprintln!("bench/ports.rs measures x86-64 ports only");
}

//! The WGSL source of each kernel of the step, generated for the dimension D (2 or 3) and the
//! precision (the real type `R`, f64 or f32) with the run's constants written in as `const`
//! values (a run compiles its kernels once). Vectors are stored as D consecutive values
//! (`array<R>`, particle i at D·i); each kernel declares only the buffers it binds, in the order
//! of its binding list in `device.rs`.
//!
//! Positions are stored relative to the particle's cell of the neighbour grid: the cell's
//! integer coordinates (`pcell`, `wall_cell`) and the offset from the cell's corner (`pos`,
//! `wall_pos`), the way the GPU SPH codes DualSPHysics and GPUSPH store them. A distance between two
//! particles is the difference of their offsets plus the whole cells between theirs (every
//! particle of a cell is stored relative to that cell, so a pair loop over a neighbour cell
//! adds that shift once and reads no cell per neighbour), so its round-off
//! is that of the offsets, a few ulps of the cell size 2h, wherever the tank stands and however
//! large it is; in f32 that is ≈ 1e-7 of the cell, where absolute f32 positions in an 80 m tank
//! would carry ≈ 5e-6 m. The corrector and the sort move a particle to its new cell.
//!
//! The physics is that of the CPU's modern step, term for term (`slosh-core`, `docs/scheme.md`):
//! Wendland C2 kernel, Tait EOS, Adami walls (their Eq. 27) floored at zero, Eq. 8's pressure
//! term with Monaghan's artificial viscosity (Eq. 10–11), the single-sum viscous operator of
//! Colagrossi et al. (2011), the continuity equation with the density diffusion of Fourtakas
//! et al. (2019), and the symplectic position Verlet of DualSPHysics (Domínguez et al. 2022).
//! Every pair is evaluated from both of its particles (a full sweep), so no two invocations
//! write one particle and no atomics touch the physics.

/// The constants a run's kernels are compiled with.
#[derive(Clone, Debug)]
pub(crate) struct ShaderConstants {
    pub(crate) dim: usize,
    pub(crate) h: f64,
    pub(crate) support: f64,
    pub(crate) mass: f64,
    pub(crate) rho0: f64,
    pub(crate) eos_b: f64,
    pub(crate) gamma: u32,
    pub(crate) c0: f64,
    pub(crate) cfl: f64,
    /// Fixed step (s), 0 for the CFL-variable one.
    pub(crate) fixed_dt: f64,
    /// Viscous bound C h² ρ0/μ (s), 0 when μ = 0.
    pub(crate) viscous_dt: f64,
    pub(crate) av_alpha: f64,
    pub(crate) av_beta: f64,
    pub(crate) av_c: f64,
    /// K μ m of the single-sum viscous operator (K = 2(D + 2)).
    pub(crate) k_mu_m: f64,
    /// −2 δ h c0 of the density diffusion (0 without).
    pub(crate) diff_coeff: f64,
    /// Fourtakas: the diffusion differences ρ − ρ_H.
    pub(crate) hydrostatic: bool,
    pub(crate) still_level: f64,
    pub(crate) gravity: f64,
    pub(crate) wall_floor: bool,
    pub(crate) domain_min: [f64; 3],
    pub(crate) domain_max: [f64; 3],
    pub(crate) dims: [u32; 3],
    pub(crate) n_fluid: u32,
    pub(crate) n_wall: u32,
    pub(crate) n_cells: u32,
    /// Single precision (f32) instead of f64.
    pub(crate) single: bool,
}

/// Threads per workgroup of every kernel.
pub(crate) const WORKGROUP: u32 = 64;
/// Threads of the one-workgroup reductions and scan.
pub(crate) const WIDE: u32 = 256;

/// The kernels of a step, in the order they run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum KernelId {
    ReducePartial,
    ReduceFinal,
    Predictor,
    CellCount,
    CellScan,
    CellScatter,
    CellOrder,
    Gather,
    Hydrostatic,
    Walls,
    Forces,
    Corrector,
    FirstOutside,
}

impl KernelId {
    pub(crate) fn name(self) -> &'static str {
        match self {
            KernelId::ReducePartial => "reduce_partial",
            KernelId::ReduceFinal => "time_step",
            KernelId::Predictor => "predictor",
            KernelId::CellCount => "cell_count",
            KernelId::CellScan => "cell_scan",
            KernelId::CellScatter => "cell_scatter",
            KernelId::CellOrder => "cell_order",
            KernelId::Gather => "gather",
            KernelId::Hydrostatic => "hydrostatic_density",
            KernelId::Walls => "adami_walls",
            KernelId::Forces => "forces",
            KernelId::Corrector => "corrector",
            KernelId::FirstOutside => "first_outside",
        }
    }

    /// The buffers the kernel binds, in binding order: (name, read_only).
    pub(crate) fn bindings(self) -> &'static [(&'static str, bool)] {
        match self {
            KernelId::ReducePartial => &[("vel", true), ("acc", true), ("partial", false)],
            KernelId::ReduceFinal => &[("partial", true), ("state", false), ("flags", false)],
            KernelId::Predictor => &[
                ("state", true),
                ("pos", false),
                ("vel", false),
                ("vel_n", false),
                ("acc", true),
                ("rho", false),
                ("rho_n", false),
                ("drho", true),
            ],
            KernelId::CellCount => &[
                ("pos", false),
                ("pcell", false),
                ("cell", false),
                ("count", false),
            ],
            KernelId::CellScan => &[("count", false), ("start", false), ("cursor", false)],
            KernelId::CellScatter => &[("cell", true), ("cursor", false), ("order", false)],
            KernelId::CellOrder => &[("start", true), ("id", true), ("order", false)],
            KernelId::Gather => &[
                ("order", true),
                ("pos", true),
                ("vel", true),
                ("vel_n", true),
                ("rho", true),
                ("rho_n", true),
                ("id", true),
                ("pcell", true),
                ("pos2", false),
                ("vel2", false),
                ("vel_n2", false),
                ("rho2", false),
                ("rho_n2", false),
                ("id2", false),
                ("pcell2", false),
            ],
            KernelId::Hydrostatic => &[
                ("pos", true),
                ("pcell", true),
                ("rho", true),
                ("rho_h", false),
                ("p", false),
            ],
            KernelId::Walls => &[
                ("body", true),
                ("start", true),
                ("pos", true),
                ("rho", true),
                ("p", true),
                ("wall_pos", true),
                ("wall_cell", true),
                ("wall_state", false),
            ],
            KernelId::Forces => &[
                ("body", true),
                ("start", true),
                ("pos", true),
                ("pcell", true),
                ("vel", true),
                ("rho", true),
                ("p", true),
                ("rho_h", true),
                ("wall_pos", true),
                ("wall_start", true),
                ("wall_state", true),
                ("acc", false),
                ("drho", false),
            ],
            KernelId::Corrector => &[
                ("state", true),
                ("pos", false),
                ("pcell", true),
                ("vel", false),
                ("vel_n", true),
                ("acc", true),
                ("rho", false),
                ("rho_n", true),
                ("drho", true),
                ("p", false),
                ("flags", false),
            ],
            KernelId::FirstOutside => &[
                ("pos", true),
                ("pcell", true),
                ("flags", true),
                ("state", false),
            ],
        }
    }

    /// Invocations the kernel runs (one per fluid particle, wall particle, cell or the one
    /// wide workgroup).
    pub(crate) fn invocations(self, c: &ShaderConstants) -> u32 {
        match self {
            KernelId::ReduceFinal | KernelId::CellScan => WIDE,
            KernelId::ReducePartial => partial_groups(c.n_fluid) * WIDE,
            KernelId::CellOrder => c.n_cells,
            KernelId::Walls => c.n_wall,
            KernelId::FirstOutside => 1,
            _ => c.n_fluid,
        }
    }

    /// Threads per workgroup.
    pub(crate) fn workgroup(self) -> u32 {
        match self {
            KernelId::ReducePartial | KernelId::ReduceFinal | KernelId::CellScan => WIDE,
            _ => WORKGROUP,
        }
    }
}

/// Workgroups of the first reduction pass over `n` particles.
pub(crate) fn partial_groups(n: u32) -> u32 {
    n.div_ceil(WIDE).max(1)
}

/// Words of the `state` buffer (R): dt, max |v|, max |a|, the first particle outside (3).
pub(crate) const STATE_WORDS: usize = 6;
/// Words of the `flags` buffer (u32): non-finite count, outside count, first outside slot.
pub(crate) const FLAG_WORDS: usize = 3;

/// An f64 constant as WGSL (the shortest text that reads back to the same f64).
fn lit(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') {
        s
    } else {
        format!("{s}.0")
    }
}

/// The shared part of every kernel: constants, the vector type and the helpers.
fn prelude(c: &ShaderConstants) -> String {
    let d = c.dim;
    let real = if c.single { "f32" } else { "f64" };
    let v = if d == 2 { "vec2<R>" } else { "vec3<R>" };
    let vi = if d == 2 { "vec2<i32>" } else { "vec3<i32>" };
    let pi = std::f64::consts::PI;
    let norm = if d == 2 {
        7.0 / (4.0 * pi * c.h * c.h)
    } else {
        21.0 / (16.0 * pi * c.h * c.h * c.h)
    };
    let mut s = String::new();
    s += &format!("alias R = {real};\nalias V = {v};\nalias VI = {vi};\nconst D: u32 = {d}u;\n");
    for (name, value) in [
        ("H", c.h),
        ("INV_H", 1.0 / c.h),
        ("SUPPORT_SQ", c.support * c.support),
        ("EPS_H2", 0.01 * c.h * c.h),
        ("NORM", norm),
        ("MASS", c.mass),
        ("RHO0", c.rho0),
        ("EOS_B", c.eos_b),
        ("C0", c.c0),
        ("CFL", c.cfl),
        ("FIXED_DT", c.fixed_dt),
        ("VISCOUS_DT", c.viscous_dt),
        ("AV_ALPHA", c.av_alpha),
        ("AV_BETA", c.av_beta),
        ("AV_C", c.av_c),
        ("K_MU_M", c.k_mu_m),
        ("DIFF_COEFF", c.diff_coeff),
        ("STILL", c.still_level),
        ("GRAVITY", c.gravity),
        ("CELL", c.support),
    ] {
        s += &format!("const {name}: R = {};\n", lit(value));
    }
    // The smallest distance a pair is evaluated at and the largest finite state, in R.
    let (tiny, huge) = if c.single {
        (1e-30, 1e30)
    } else {
        (1e-150, 1e300)
    };
    s += &format!(
        "const TINY: R = {};\nconst HUGE: R = {};\n",
        lit(tiny),
        lit(huge)
    );
    s += &format!("const GAMMA: u32 = {}u;\n", c.gamma);
    s += &format!(
        "const WIDE: u32 = {WIDE}u;\nconst WIDE_HALF: u32 = {}u;\n",
        WIDE / 2
    );
    s += &format!(
        "const N_FLUID: u32 = {}u;\nconst N_WALL: u32 = {}u;\n",
        c.n_fluid, c.n_wall
    );
    s += &format!("const N_CELLS: u32 = {}u;\n", c.n_cells);
    s += &format!(
        "const AV_ON: bool = {};\nconst HYDRO: bool = {};\nconst WALL_FLOOR: bool = {};\n",
        c.av_alpha > 0.0 || c.av_beta > 0.0,
        c.hydrostatic,
        c.wall_floor
    );
    let comps = |a: [f64; 3]| {
        (0..d)
            .map(|k| format!("R({})", lit(a[k])))
            .collect::<Vec<_>>()
            .join(", ")
    };
    s += &format!("const LO: V = V({});\n", comps(c.domain_min));
    s += &format!("const HI: V = V({});\n", comps(c.domain_max));
    let dims = (0..d)
        .map(|k| format!("{}", c.dims[k]))
        .collect::<Vec<_>>()
        .join(", ");
    s += &format!("const DIMS: VI = VI({dims});\n");
    s += &format!("const STENCIL: u32 = {}u;\n", 3u32.pow(d as u32));
    // The offset of stencil cell k (0 … 3^D − 1) in {−1, 0, 1}^D, x fastest.
    s += if d == 2 {
        "fn stencil(k: u32) -> VI { return VI(i32(k % 3u) - 1, i32(k / 3u) - 1); }\n"
    } else {
        "fn stencil(k: u32) -> VI { return VI(i32(k % 3u) - 1, i32((k / 3u) % 3u) - 1, i32(k / 9u) - 1); }\n"
    };
    s += if d == 2 {
        "fn cell_index(c: VI) -> u32 { return u32(c.x) + u32(DIMS.x) * u32(c.y); }\n\
         fn inside_grid(c: VI) -> bool { return all(c >= VI(0)) && all(c < DIMS); }\n"
    } else {
        "fn cell_index(c: VI) -> u32 { return u32(c.x) + u32(DIMS.x) * (u32(c.y) + u32(DIMS.y) * u32(c.z)); }\n\
         fn inside_grid(c: VI) -> bool { return all(c >= VI(0)) && all(c < DIMS); }\n"
    };
    s += r#"
// The absolute position of a point given as (offset, cell) (for the depth and the domain
// check, where the round-off of an absolute coordinate does no harm).
fn absolute(x: V, c: VI) -> V {
    return LO + V(c) * CELL + x;
}

// Eq. 18: Tait EOS p = B((ρ/ρ0)^γ − 1), γ a whole number.
fn eos(rho: R) -> R {
    let r = rho / RHO0;
    var power = r;
    for (var k = 1u; k < GAMMA; k++) { power = power * r; }
    return EOS_B * (power - R(1.0));
}

// y^(1/n) for y > 0: a single-precision start refined by Newton's method on x^n = y
// (each step squares the relative error: 1e-7 → 1e-14 → round-off).
fn root(y: R, n: u32) -> R {
    var x = R(pow(f32(y), 1.0 / f32(n)));
    for (var it = 0u; it < 3u; it++) {
        var xn1 = R(1.0);
        for (var k = 1u; k < n; k++) { xn1 = xn1 * x; }
        x = x - (xn1 * x - y) / (R(n) * xn1);
    }
    return x;
}

// The inverse EOS ρ0 (1 + p/B)^(1/γ) (the base floored at 1e-6, as the CPU's).
fn density_of(p: R) -> R {
    return RHO0 * root(max(R(1.0) + p / EOS_B, R(1e-6)), GAMMA);
}

// Wendland C2: W = NORM (1 − q/2)^4 (2q + 1) for q = r/h < 2.
fn kernel_value(r: R) -> R {
    let q = r * INV_H;
    let t = max(R(1.0) - R(0.5) * q, R(0.0));
    let t2 = t * t;
    return NORM * t2 * t2 * (R(2.0) * q + R(1.0));
}

// (dW/dr)/r = −5 NORM (1 − q/2)^3 / h².
fn gradient_factor(r: R) -> R {
    let q = r * INV_H;
    let t = max(R(1.0) - R(0.5) * q, R(0.0));
    return R(-5.0) * NORM * t * t * t * INV_H * INV_H;
}
"#;
    s
}

/// Loads and stores of a vector buffer `name` (D consecutive values).
fn vec_access(name: &str, d: usize, write: bool) -> String {
    let comps = (0..d)
        .map(|k| format!("{name}[D * i + {k}u]"))
        .collect::<Vec<_>>()
        .join(", ");
    let ty = if is_cell(name) { "VI" } else { "V" };
    let mut s = format!("fn get_{name}(i: u32) -> {ty} {{ return {ty}({comps}); }}\n");
    if write {
        s += &format!("fn set_{name}(i: u32, v: {ty}) {{ ");
        for k in 0..d {
            s += &format!("{name}[D * i + {k}u] = v[{k}]; ");
        }
        s += "}\n";
    }
    s
}

/// The element type of each buffer.
fn element(name: &str) -> &'static str {
    match name {
        "cell" | "order" | "id" | "id2" | "start" | "wall_start" => "u32",
        "count" | "cursor" | "flags" => "atomic<u32>",
        n if is_cell(n) => "i32",
        _ => "R",
    }
}

/// The buffers of cell coordinates (D i32 per particle).
pub(crate) fn is_cell(name: &str) -> bool {
    matches!(name, "pcell" | "pcell2" | "wall_cell")
}

/// Vector buffers (D values per particle).
fn is_vector(name: &str) -> bool {
    matches!(
        name,
        "pos"
            | "vel"
            | "vel_n"
            | "acc"
            | "pos2"
            | "vel2"
            | "vel_n2"
            | "wall_pos"
            | "body"
            | "pcell"
            | "pcell2"
            | "wall_cell"
    )
}

/// The WGSL of one kernel.
pub(crate) fn source(id: KernelId, c: &ShaderConstants) -> String {
    let mut s = prelude(c);
    for (b, (name, read_only)) in id.bindings().iter().enumerate() {
        let elem = if *name == "flags" && *read_only {
            "u32"
        } else {
            element(name)
        };
        let access = if *read_only { "read" } else { "read_write" };
        s += &format!("@group(0) @binding({b}) var<storage, {access}> {name}: array<{elem}>;\n");
        if is_vector(name) {
            s += &vec_access(name, c.dim, !read_only);
        }
    }
    s += &format!(
        "@compute @workgroup_size({})\nfn main(@builtin(global_invocation_id) gid: vec3<u32>, \
         @builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {{\n",
        id.workgroup()
    );
    s += body(id);
    s += "}\n";
    s = workgroup_arrays(id) + &s;
    s
}

/// Workgroup-shared arrays of the reductions and the scan (declared before the entry point).
fn workgroup_arrays(id: KernelId) -> String {
    match id {
        KernelId::ReducePartial | KernelId::ReduceFinal => {
            format!("var<workgroup> red_v: array<R, {WIDE}>;\nvar<workgroup> red_a: array<R, {WIDE}>;\n")
        }
        KernelId::CellScan => format!("var<workgroup> sums: array<u32, {WIDE}>;\n"),
        _ => String::new(),
    }
}

/// The body of each kernel's entry point.
fn body(id: KernelId) -> &'static str {
    match id {
        // Largest |v|² and |a|² of each block of WIDE particles.
        KernelId::ReducePartial => {
            r#"
    let i = gid.x;
    var v2 = R(0.0);
    var a2 = R(0.0);
    if (i < N_FLUID) {
        let v = get_vel(i);
        let a = get_acc(i);
        v2 = dot(v, v);
        a2 = dot(a, a);
    }
    red_v[lid.x] = v2;
    red_a[lid.x] = a2;
    workgroupBarrier();
    for (var width = WIDE_HALF; width > 0u; width = width / 2u) {
        if (lid.x < width) {
            red_v[lid.x] = max(red_v[lid.x], red_v[lid.x + width]);
            red_a[lid.x] = max(red_a[lid.x], red_a[lid.x + width]);
        }
        workgroupBarrier();
    }
    if (lid.x == 0u) {
        partial[2u * wid.x] = red_v[0];
        partial[2u * wid.x + 1u] = red_a[0];
    }
"#
        }
        // The maxima of the blocks, then the step length of the CPU's `time_step`: C h/(c0 +
        // |v|max), C √(h/|a|max), the viscous bound, or the fixed dt. Clears the flags.
        KernelId::ReduceFinal => {
            r#"
    let groups = arrayLength(&partial) / 2u;
    var v2 = R(0.0);
    var a2 = R(0.0);
    for (var g = lid.x; g < groups; g += WIDE) {
        v2 = max(v2, partial[2u * g]);
        a2 = max(a2, partial[2u * g + 1u]);
    }
    red_v[lid.x] = v2;
    red_a[lid.x] = a2;
    workgroupBarrier();
    for (var width = WIDE_HALF; width > 0u; width = width / 2u) {
        if (lid.x < width) {
            red_v[lid.x] = max(red_v[lid.x], red_v[lid.x + width]);
            red_a[lid.x] = max(red_a[lid.x], red_a[lid.x + width]);
        }
        workgroupBarrier();
    }
    if (lid.x == 0u) {
        let vmax = sqrt(red_v[0]);
        let amax = sqrt(red_a[0]);
        var dt = CFL * H / (C0 + vmax);
        if (amax > R(0.0)) { dt = min(dt, CFL * sqrt(H / amax)); }
        if (VISCOUS_DT > R(0.0)) { dt = min(dt, VISCOUS_DT); }
        if (FIXED_DT > R(0.0)) { dt = FIXED_DT; }
        state[0] = dt;
        state[1] = vmax;
        state[2] = amax;
        atomicStore(&flags[0], 0u);
        atomicStore(&flags[1], 0u);
        atomicStore(&flags[2], 0xffffffffu);
    }
"#
        }
        // x^{n+½} = x^n + dt/2 v^n; v^n kept in vel_n; the mid-step estimate v^n + dt/2 a in
        // vel; ρ^n kept in rho_n, ρ^{n+½} = ρ^n + dt/2 Dρ (its pressure after the sort).
        KernelId::Predictor => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    let half = R(0.5) * state[0];
    let v = get_vel(i);
    set_pos(i, get_pos(i) + half * v);
    set_vel_n(i, v);
    set_vel(i, v + half * get_acc(i));
    let r = rho[i];
    rho_n[i] = r;
    rho[i] = r + half * drho[i];
"#
        }
        // The particle's new cell (its offset moved by the whole cells it left it by, the cell
        // clamped into the grid: a particle outside the domain is a blow-up, reported by the
        // corrector), then the count of its cell.
        KernelId::CellCount => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    let old = get_pcell(i);
    let x = get_pos(i);
    let moved = clamp(old + VI(floor(x / CELL)), VI(0), DIMS - VI(1));
    set_pos(i, x - V(moved - old) * CELL);
    set_pcell(i, moved);
    let c = cell_index(moved);
    cell[i] = c;
    atomicAdd(&count[c], 1u);
"#
        }
        // Exclusive prefix sum of the cell counts into start (and the scatter cursors), one
        // workgroup: each thread sums a contiguous chunk, the chunk totals are scanned, each
        // thread writes its chunk. Clears the counts for the next step. start[N_CELLS] = n.
        KernelId::CellScan => {
            r#"
    let chunk = (N_CELLS + WIDE - 1u) / WIDE;
    let first = lid.x * chunk;
    let last = min(first + chunk, N_CELLS);
    var total = 0u;
    for (var k = first; k < last; k++) { total += atomicLoad(&count[k]); }
    sums[lid.x] = total;
    workgroupBarrier();
    if (lid.x == 0u) {
        var run = 0u;
        for (var t = 0u; t < WIDE; t++) {
            let s = sums[t];
            sums[t] = run;
            run += s;
        }
        start[N_CELLS] = run;
    }
    workgroupBarrier();
    var run = sums[lid.x];
    for (var k = first; k < last; k++) {
        start[k] = run;
        atomicStore(&cursor[k], run);
        run += atomicLoad(&count[k]);
        atomicStore(&count[k], 0u);
    }
"#
        }
        KernelId::CellScatter => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    let slot = atomicAdd(&cursor[cell[i]], 1u);
    order[slot] = i;
"#
        }
        // The particles of a cell in the order of their ids, so that the sums of the pair
        // loops are added in an order that does not depend on the scatter's atomics.
        KernelId::CellOrder => {
            r#"
    let c = gid.x;
    if (c >= N_CELLS) { return; }
    let a = start[c];
    let b = start[c + 1u];
    for (var k = a + 1u; k < b; k++) {
        let item = order[k];
        let key = id[item];
        var m = k;
        while (m > a && id[order[m - 1u]] > key) {
            order[m] = order[m - 1u];
            m = m - 1u;
        }
        order[m] = item;
    }
"#
        }
        KernelId::Gather => {
            r#"
    let s = gid.x;
    if (s >= N_FLUID) { return; }
    let i = order[s];
    set_pos2(s, get_pos(i));
    set_vel2(s, get_vel(i));
    set_vel_n2(s, get_vel_n(i));
    rho2[s] = rho[i];
    rho_n2[s] = rho_n[i];
    id2[s] = id[i];
    set_pcell2(s, get_pcell(i));
"#
        }
        // The pressure of the sorted ρ^{n+½}, and ρ_H = ρ0 (1 + ρ0 g z (γ−1)/(γB))^(1/(γ−1)),
        // z = z_s − z below the still level: the Tait density of the exact hydrostatic
        // pressure (the CPU's `hydrostatic_density`, its base floored as there).
        KernelId::Hydrostatic => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    p[i] = eos(rho[i]);
    let depth = STILL - absolute(get_pos(i), get_pcell(i))[D - 1u];
    let g = R(GAMMA);
    let base = R(1.0) + RHO0 * GRAVITY * depth * (g - R(1.0)) / (g * EOS_B);
    var rh = RHO0 * root(R(1e-6), GAMMA);
    if (base > R(0.0)) {
        rh = max(RHO0 * root(base, GAMMA - 1u), rh);
    }
    rho_h[i] = rh;
"#
        }
        // Adami, Hu & Adams (2012) Eq. 27: p_w = (Σ p_f W + b·Σ ρ_f (x_w − x_f) W)/Σ W over
        // the fluid within the support, floored at 0 (`wall_separation`); ρ_w from the
        // inverse EOS; p = 0, ρ = ρ0 for a wall with no fluid near. wall_state holds (p, ρ).
        KernelId::Walls => {
            r#"
    let w = gid.x;
    if (w >= N_WALL) { return; }
    let xw = get_wall_pos(w);
    let b = get_body(0u);
    let home = get_wall_cell(w);
    var sum_w = R(0.0);
    var sum_pw = R(0.0);
    var sum_rx = V(R(0.0));
    for (var k = 0u; k < STENCIL; k++) {
        let cc = home + stencil(k);
        if (!inside_grid(cc)) { continue; }
        let ci = cell_index(cc);
        // Every particle of cell cc is stored relative to cc (the sort put it there).
        let base = xw + V(home - cc) * CELL;
        for (var j = start[ci]; j < start[ci + 1u]; j++) {
            let d = base - get_pos(j);
            let r2 = dot(d, d);
            if (r2 < SUPPORT_SQ) {
                let wv = kernel_value(sqrt(r2));
                sum_w += wv;
                sum_pw += p[j] * wv;
                sum_rx += d * (rho[j] * wv);
            }
        }
    }
    var pw = R(0.0);
    var rw = RHO0;
    if (sum_w > R(1e-12)) {
        pw = (sum_pw + dot(b, sum_rx)) / sum_w;
        if (WALL_FLOOR) { pw = max(pw, R(0.0)); }
        rw = density_of(pw);
    }
    wall_state[2u * w] = pw;
    wall_state[2u * w + 1u] = rw;
"#
        }
        // The coupled pair pass of the modern step for fluid particle i: Eq. 8's pressure
        // term, Eq. 10's artificial viscosity, the single-sum viscous operator and the
        // continuity equation with the δ-SPH diffusion against every fluid neighbour; the
        // pressure term and the continuity term against the Adami wall particles.
        KernelId::Forces => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    let xi = get_pos(i);
    let home = get_pcell(i);
    let vi = get_vel(i);
    let rho_i = rho[i];
    let inv_rho_i = R(1.0) / rho_i;
    let p_i = p[i];
    var dyn_i = rho_i;
    if (HYDRO) { dyn_i = rho_i - rho_h[i]; }
    var acc = V(R(0.0));
    var drho_i = R(0.0);
    for (var k = 0u; k < STENCIL; k++) {
        let cc = home + stencil(k);
        if (!inside_grid(cc)) { continue; }
        let ci = cell_index(cc);
        // Every fluid and wall particle of cell cc is stored relative to cc.
        let base = xi + V(home - cc) * CELL;
        for (var j = start[ci]; j < start[ci + 1u]; j++) {
            if (j == i) { continue; }
            let xij = base - get_pos(j);
            let r2 = dot(xij, xij);
            if (r2 >= SUPPORT_SQ) { continue; }
            let r = max(sqrt(r2), TINY);
            let f = gradient_factor(r);
            let inv_s = R(1.0) / (r2 + EPS_H2);
            let rho_j = rho[j];
            let inv_rho_mean = R(2.0) / (rho_i + rho_j);
            let inv_rho_ij = inv_rho_i / rho_j;
            let vij = vi - get_vel(j);
            let vx = dot(vij, xij);
            var scalar = -(p_i + p[j]) * inv_rho_ij * MASS;
            if (AV_ON) {
                let phi = H * min(vx, R(0.0)) * inv_s;
                scalar -= MASS * (-AV_ALPHA * AV_C * phi + AV_BETA * phi * phi) * inv_rho_mean;
            }
            scalar += K_MU_M * vx * inv_rho_ij * inv_s;
            acc += xij * (f * scalar);
            drho_i += MASS * vx * f;
            if (DIFF_COEFF != R(0.0)) {
                var dyn_j = rho_j;
                if (HYDRO) { dyn_j = rho_j - rho_h[j]; }
                drho_i += DIFF_COEFF * (dyn_j - dyn_i) * f * (MASS / rho_j);
            }
        }
        for (var w = wall_start[ci]; w < wall_start[ci + 1u]; w++) {
            let xiw = base - get_wall_pos(w);
            let r2 = dot(xiw, xiw);
            if (r2 >= SUPPORT_SQ) { continue; }
            let r = max(sqrt(r2), TINY);
            let f = gradient_factor(r);
            let pw = wall_state[2u * w];
            let rw = wall_state[2u * w + 1u];
            acc += xiw * (f * MASS * (-(p_i + pw) * inv_rho_i / rw));
            drho_i += MASS * dot(vi, xiw) * f;
        }
    }
    set_acc(i, acc + get_body(0u));
    drho[i] = drho_i;
"#
        }
        // v^{n+1} = v^n + dt a; x^{n+1} = x^{n+½} + dt/2 v^{n+1}; ρ^{n+1} = ρ^n (2 − ε)/(2 + ε),
        // ε = −(Dρ/ρ^{n+½}) dt; the pressure; the blow-up counts.
        KernelId::Corrector => {
            r#"
    let i = gid.x;
    if (i >= N_FLUID) { return; }
    let dt = state[0];
    let v = get_vel_n(i) + dt * get_acc(i);
    let x = get_pos(i) + (R(0.5) * dt) * v;
    set_vel(i, v);
    set_pos(i, x);
    let eps = -drho[i] / rho[i] * dt;
    let r = rho_n[i] * (R(2.0) - eps) / (R(2.0) + eps);
    rho[i] = r;
    p[i] = eos(r);
    let s = dot(x, x) + dot(v, v);
    let at = absolute(x, get_pcell(i));
    if (!(s < HUGE)) {
        atomicAdd(&flags[0], 1u);
    } else if (any(at < LO) || any(at > HI)) {
        atomicAdd(&flags[1], 1u);
        atomicMin(&flags[2], i);
    }
"#
        }
        KernelId::FirstOutside => {
            r#"
    if (gid.x != 0u) { return; }
    let s = flags[2];
    if (s < N_FLUID) {
        let x = absolute(get_pos(s), get_pcell(s));
        for (var k = 0u; k < D; k++) { state[3u + k] = x[k]; }
    }
"#
        }
    }
}

/// The WGSL of a kernel.
pub(crate) fn kernel_source(id: KernelId, c: &ShaderConstants) -> String {
    source(id, c)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Constants print as WGSL float literals that read back to the same f64.
    #[test]
    fn literals_round_trip() {
        for x in [0.1, 1e-17, 2.0, 1013000.0, -5.0, 123.456e-7] {
            let s = lit(x);
            assert!(s.contains('.') || s.contains('e'), "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), x);
        }
    }
}

//! Contacts solved as contacts: one constraint per manifold, coloured, packed into SIMD
//! batches and solved lane-parallel in the soft step's stages (see `kernel` for the maths and
//! `batch` for the data).
//!
//! Prepare colours the step's contacts (`graph`), orders each colour's contacts by point count
//! so that a batch's lanes have as many points as each other, and writes them into batches of
//! the lane width chosen at run time (8 `f32` lanes with AVX2, 4 with SSE2, or 1). Contacts that
//! found no colour form the overflow, solved one at a time before the colours in every stage.
//! Every stage runs colour after colour; within a colour no body appears twice, so the lanes
//! (and, with the `parallel` feature, the threads) never write the same body.

mod batch;
mod kernel;
mod store;

use super::super::integrate::BodyScratch;
use super::super::wide::{FloatW, Records, SimdLevel};
use super::super::{reserve, SolverBody, SolverContact};
use super::bodies::{delta_records, vel_records, BodyStates};
use super::disjoint::Disjoint;
use super::graph::{Colouring, COLOURS, OVERFLOW};
use crate::cache::prefetch;
use crate::math::{Real, Vec3};
use batch::ContactBatch;
pub(crate) use batch::PrepareParams;
pub(crate) use kernel::KernelParams;

#[cfg(target_arch = "x86_64")]
use super::super::wide::{Narrow, Wide};

/// One contact of the step as the solver files it.
#[derive(Debug, Clone, Copy)]
struct Entry {
    /// Index in the solver's contact slice.
    index: u32,
    a: u32,
    b: u32,
    colour: u8,
    points: u8,
}

/// The batches of one lane width, colour after colour.
#[derive(Debug, Default, Clone)]
struct Lanes<F: FloatW> {
    batches: Vec<ContactBatch<F>>,
    /// `batches[colour_start[c]..colour_start[c + 1]]` are colour c's.
    colour_start: Vec<u32>,
}

/// A stage of the soft step, as far as contacts are concerned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stage {
    WarmStart,
    Solve,
    Relax,
    Restitution,
}

/// Runs `stage` over `batches`.
#[inline(always)]
fn run_batches<F: FloatW>(
    batches: &mut [ContactBatch<F>],
    stage: Stage,
    vel: Records<'_>,
    delta: Records<'_>,
    k: &KernelParams,
) {
    for c in batches {
        match stage {
            Stage::WarmStart => kernel::warm_start(c, vel, k),
            Stage::Solve => kernel::solve(c, vel, delta, k, true),
            Stage::Relax => kernel::solve(c, vel, delta, k, false),
            Stage::Restitution => kernel::restitution(c, vel, delta, k),
        }
    }
}

/// Computes the derived data of `batches` (see `batch`).
#[inline(always)]
fn derive_batches<F: FloatW>(
    batches: &mut [ContactBatch<F>],
    vel: Records<'_>,
    forcing: Records<'_>,
) {
    for c in batches {
        batch::derive(c, vel, forcing);
    }
}

/// [`run_batches`] for 8 lanes (4 in `f64`), compiled for AVX2.
///
/// # Safety
/// Only call where AVX2 and FMA were detected ([`SimdLevel::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn run_batches_wide(
    batches: &mut [ContactBatch<Wide>],
    stage: Stage,
    vel: Records<'_>,
    delta: Records<'_>,
    k: &KernelParams,
) {
    run_batches(batches, stage, vel, delta, k);
}

/// [`derive_batches`] for 8 lanes (4 in `f64`), compiled for AVX2.
///
/// # Safety
/// Only call where AVX2 and FMA were detected ([`SimdLevel::detect`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn derive_batches_wide(
    batches: &mut [ContactBatch<Wide>],
    vel: Records<'_>,
    forcing: Records<'_>,
) {
    derive_batches(batches, vel, forcing);
}

/// Batches one thread takes at a time with the `parallel` feature. A batch's result does not
/// depend on which thread ran it, so every thread count gives bit-identical results.
#[cfg(feature = "parallel")]
const CHUNK: usize = 16;

/// The fewest batches of one colour worth handing to other threads in a contact pass (fewer
/// run on the calling thread). Waking a worker costs tens of microseconds on a virtual
/// machine, and a solve pass over 128 batches takes about 40 µs: measured on 2 cores, 32
/// left a 210-box pyramid at 0.87 of its one-thread speed and 1,000 balls at 0.80.
#[cfg(feature = "parallel")]
const PARALLEL_MIN_BATCHES: usize = 8 * CHUNK;

/// The same for the passes over every batch of the step at once (deriving, storing): light
/// work, so it waits for a bigger world (with 256, an 820-box pyramid ran at 0.89 of its
/// one-thread speed on 2 cores).
#[cfg(feature = "parallel")]
const PARALLEL_MIN_PASS: usize = 32 * CHUNK;

/// Calls `f(first, chunk)` on `batches` in chunks (`first`: the chunk's index of its first
/// batch), on all cores with the `parallel` feature (`whole_pass`: one pass over every batch
/// of the step, with its own threshold). The batches must share no writable body (one
/// colour), or `f` must write no body.
#[inline(always)]
fn for_each_chunk<F: FloatW>(
    batches: &mut [ContactBatch<F>],
    whole_pass: bool,
    f: impl Fn(usize, &mut [ContactBatch<F>]) + Sync + Send,
) {
    #[cfg(feature = "parallel")]
    let least = if whole_pass {
        PARALLEL_MIN_PASS
    } else {
        PARALLEL_MIN_BATCHES
    };
    #[cfg(not(feature = "parallel"))]
    let _ = whole_pass;
    #[cfg(feature = "parallel")]
    if batches.len() >= least {
        use rayon::prelude::*;
        batches
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each_init(crate::float_mode::FlushSubnormals::new, |_, (i, chunk)| {
                f(i * CHUNK, chunk)
            });
        return;
    }
    f(0, batches);
}

impl<F: FloatW> Lanes<F> {
    fn bytes(&self) -> usize {
        self.batches.capacity() * std::mem::size_of::<ContactBatch<F>>()
            + self.colour_start.capacity() * 4
    }

    /// Computes every batch's derived data with `derive` (bodies are only read).
    fn derive(
        &mut self,
        vel: Records<'_>,
        forcing: Records<'_>,
        derive: fn(&mut [ContactBatch<F>], Records<'_>, Records<'_>),
    ) {
        for_each_chunk(&mut self.batches, true, |_, b| derive(b, vel, forcing));
    }

    /// Runs one stage over every batch with `run`, colour after colour (the batches of a
    /// colour side by side).
    fn run(
        &mut self,
        stage: Stage,
        vel: Records<'_>,
        delta: Records<'_>,
        k: &KernelParams,
        run: BatchRunner<F>,
    ) {
        for c in 0..self.colour_start.len().saturating_sub(1) {
            let range = self.colour_start[c] as usize..self.colour_start[c + 1] as usize;
            for_each_chunk(&mut self.batches[range], false, |_, b| {
                run(b, stage, vel, delta, k)
            });
        }
    }
}

/// A stage over some batches, compiled for one lane width.
type BatchRunner<F> = fn(&mut [ContactBatch<F>], Stage, Records<'_>, Records<'_>, &KernelParams);

/// The contact solver's workspace.
#[derive(Debug, Default, Clone)]
pub(crate) struct ContactSolver {
    level: SimdLevel,
    colouring: Colouring,
    entries: Vec<Entry>,
    order: Vec<u32>,
    colour_count: Vec<u32>,
    bucket: Vec<u32>,
    overflow: Lanes<Real>,
    scalar: Lanes<Real>,
    #[cfg(target_arch = "x86_64")]
    narrow: Lanes<Narrow>,
    #[cfg(target_arch = "x86_64")]
    wide: Lanes<Wide>,
}

impl ContactSolver {
    pub(crate) fn reserve(&mut self, bodies: usize, contacts: usize) {
        self.colouring.reserve(bodies);
        reserve(&mut self.entries, contacts);
        reserve(&mut self.order, contacts);
        let level = SimdLevel::Auto.detect();
        let lanes = level.lanes();
        let batches = contacts / lanes + COLOURS + 1;
        reserve(&mut self.overflow.batches, contacts.min(64));
        match level {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Wide => reserve(&mut self.wide.batches, batches),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Narrow => reserve(&mut self.narrow.batches, batches),
            _ => reserve(&mut self.scalar.batches, batches),
        }
    }

    pub(crate) fn bytes(&self) -> usize {
        let mut n = self.colouring.bytes()
            + self.entries.capacity() * std::mem::size_of::<Entry>()
            + (self.order.capacity() + self.colour_count.capacity() + self.bucket.capacity()) * 4
            + self.overflow.bytes()
            + self.scalar.bytes();
        #[cfg(target_arch = "x86_64")]
        {
            n += self.narrow.bytes() + self.wide.bytes();
        }
        n
    }

    pub(crate) fn bytes_for(bodies: usize, contacts: usize) -> usize {
        let lanes = SimdLevel::Auto.lanes();
        let batch = std::mem::size_of::<ContactBatch<Real>>() * lanes;
        (bodies + 1) * 4 + contacts * (std::mem::size_of::<Entry>() + 4) + contacts * batch
    }

    /// Starts a step.
    pub(crate) fn begin(&mut self) {
        self.entries.clear();
    }

    /// Files contact `index` (on local bodies `a`, `b`) for this step.
    pub(crate) fn add(&mut self, index: u32, contact: &SolverContact, a: u32, b: u32) {
        let points = contact.contact.points().len() as u8;
        self.entries.push(Entry {
            index,
            a,
            b,
            colour: OVERFLOW,
            points,
        });
    }

    /// Colours used and contacts in the overflow.
    pub(crate) fn colour_stats(&self) -> (u32, u32) {
        let used = self.colour_count[..COLOURS]
            .iter()
            .filter(|&&n| n > 0)
            .count() as u32;
        (used, self.colour_count[COLOURS])
    }

    /// The lane width in use.
    pub(crate) fn lanes(&self) -> u32 {
        self.level.lanes() as u32
    }

    /// Colours the filed contacts and writes them into batches of the lane width `level`.
    pub(crate) fn prepare(
        &mut self,
        contacts: &[SolverContact],
        bodies: &[SolverBody],
        states: &mut BodyStates,
        level: SimdLevel,
        k: &PrepareParams,
    ) {
        self.level = level.detect();
        self.colour(states);
        self.order_by_colour_and_points();
        let position = |slot: u32| {
            let g = states.global[slot as usize];
            if slot == 0 {
                Vec3::ZERO
            } else {
                bodies[g as usize].position
            }
        };
        let split = self.order.len() - self.colour_count[COLOURS] as usize;
        let (coloured, overflow) = self.order.split_at(split);
        let source = LoadSource {
            entries: &self.entries,
            colour_count: &self.colour_count,
            contacts,
            states,
            position: &position,
            k,
        };
        build(&mut self.overflow, overflow, true, &source);
        match self.level {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Wide => build(&mut self.wide, coloured, false, &source),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Narrow => build(&mut self.narrow, coloured, false, &source),
            _ => build(&mut self.scalar, coloured, false, &source),
        }
        let (vel, forcing) = (
            vel_records(&mut states.vel),
            vel_records(&mut states.forcing),
        );
        self.overflow.derive(vel, forcing, derive_batches);
        match self.level {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Wide => self.wide.derive(vel, forcing, |b, v, f| {
                // SAFETY: `level` is `Wide` only where AVX2 and FMA were detected.
                unsafe { derive_batches_wide(b, v, f) }
            }),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Narrow => self.narrow.derive(vel, forcing, derive_batches),
            _ => self.scalar.derive(vel, forcing, derive_batches),
        }
    }

    /// Gives each filed contact a colour (no body twice in one colour among the bodies the
    /// colours write; the rest overflow) and counts each colour's contacts.
    fn colour(&mut self, states: &BodyStates) {
        self.colouring.begin(states.len());
        self.colour_count.clear();
        self.colour_count.resize(COLOURS + 1, 0);
        for e in &mut self.entries {
            let (wa, wb) = (states.writable[e.a as usize], states.writable[e.b as usize]);
            e.colour = self.colouring.assign(e.a, wa, e.b, wb);
            let c = if e.colour == OVERFLOW {
                COLOURS
            } else {
                e.colour as usize
            };
            self.colour_count[c] += 1;
        }
    }

    /// Orders the contacts by colour, then most points first (a stable counting sort), so
    /// that the lanes of a batch have as many points as each other.
    fn order_by_colour_and_points(&mut self) {
        const P: usize = crate::constraint::MAX_CONTACT_POINTS;
        let key = |e: &Entry| {
            let c = if e.colour == OVERFLOW {
                COLOURS
            } else {
                e.colour as usize
            };
            c * P + (P - e.points as usize)
        };
        self.bucket.clear();
        self.bucket.resize((COLOURS + 1) * P + 1, 0);
        for e in &self.entries {
            self.bucket[key(e) + 1] += 1;
        }
        for i in 1..self.bucket.len() {
            self.bucket[i] += self.bucket[i - 1];
        }
        self.order.clear();
        self.order.resize(self.entries.len(), 0);
        for (i, e) in self.entries.iter().enumerate() {
            let slot = &mut self.bucket[key(e)];
            self.order[*slot as usize] = i as u32;
            *slot += 1;
        }
    }

    /// Runs one stage: the overflow, then every colour.
    pub(crate) fn run(&mut self, stage: Stage, states: &mut BodyStates, k: &KernelParams) {
        let (vel, delta) = (
            vel_records(&mut states.vel),
            delta_records(&mut states.delta),
        );
        // The overflow's contacts share bodies: one at a time, on this thread.
        run_batches(&mut self.overflow.batches, stage, vel, delta, k);
        match self.level {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Wide => self.wide.run(stage, vel, delta, k, |b, s, v, d, k| {
                // SAFETY: `level` is `Wide` only where AVX2 and FMA were detected.
                unsafe { run_batches_wide(b, s, v, d, k) }
            }),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Narrow => self.narrow.run(stage, vel, delta, k, run_batches),
            _ => self.scalar.run(stage, vel, delta, k, run_batches),
        }
    }

    /// Writes every point's forces back to its contact (mean over the step, and the last
    /// substep's as the next warm start) and adds them to the bodies' constraint forces.
    pub(crate) fn store(
        &mut self,
        contacts: &mut [SolverContact],
        states: &BodyStates,
        scratch: &mut BodyScratch,
        (h, hs): (Real, Real),
        body_forces: bool,
    ) {
        // Each body's force sums, only for a caller that reads them.
        let mut sums = body_forces.then_some(scratch);
        store_lanes(
            &mut self.overflow,
            contacts,
            states,
            sums.as_deref_mut(),
            (h, hs),
        );
        match self.level {
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Wide => store_lanes(&mut self.wide, contacts, states, sums, (h, hs)),
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Narrow => store_lanes(&mut self.narrow, contacts, states, sums, (h, hs)),
            _ => store_lanes(&mut self.scalar, contacts, states, sums, (h, hs)),
        }
    }
}

/// Writes the contacts of `order` (already sorted by colour) into `lanes`' batches, reusing
/// last step's batches: every lane and point is written, so nothing is zeroed twice.
#[allow(clippy::too_many_arguments)]
fn build<F: FloatW>(lanes: &mut Lanes<F>, order: &[u32], overflow: bool, source: &LoadSource<'_>) {
    let LoadSource {
        entries,
        colour_count,
        contacts,
        states,
        position,
        k,
    } = *source;
    lanes.colour_start.clear();
    let colours: &[u32] = if overflow {
        &colour_count[COLOURS..]
    } else {
        &colour_count[..COLOURS]
    };
    let mut next = 0;
    let mut used = 0;
    for &count in colours {
        lanes.colour_start.push(used as u32);
        let count = count as usize;
        let batches = count.div_ceil(F::LANES);
        if lanes.batches.len() < used + batches {
            lanes.batches.resize_with(used + batches, Default::default);
        }
        let colour = &order[next..next + count];
        // Each batch is filled from its own contacts: the colour's batches side by side.
        for_each_chunk(
            &mut lanes.batches[used..used + batches],
            false,
            |first, chunk| {
                for (b, batch) in chunk.iter_mut().enumerate() {
                    let start = (first + b) * F::LANES;
                    let mine = &colour[start..(start + F::LANES).min(count)];
                    batch.points = 0;
                    for (l, &o) in mine.iter().enumerate() {
                        // Colour order visits the contacts out of order: fetch a few ahead.
                        if let Some(&ahead) = colour.get(start + l + PREFETCH_AHEAD) {
                            prefetch(&contacts[entries[ahead as usize].index as usize]);
                        }
                        let e = &entries[o as usize];
                        let c = &contacts[e.index as usize];
                        batch.load_lane(
                            l,
                            e.index,
                            &c.contact,
                            (e.a, e.b),
                            (position(e.a), position(e.b)),
                            states,
                            k,
                        );
                    }
                    for l in 0..F::LANES {
                        match mine.get(l) {
                            None => batch.clear_lane(l),
                            Some(&o) => {
                                let n = entries[o as usize].points as usize;
                                if n < batch.points as usize {
                                    batch.clear_points(l, n);
                                }
                            }
                        }
                    }
                }
            },
        );
        next += count;
        used += batches;
    }
    lanes.batches.truncate(used);
    lanes.colour_start.push(used as u32);
}

/// What the batches' lanes are loaded from: the step's contact entries in colour order, the
/// contacts, the bodies' states and positions, and the step's parameters.
struct LoadSource<'a> {
    entries: &'a [Entry],
    colour_count: &'a [u32],
    contacts: &'a [SolverContact],
    states: &'a BodyStates,
    position: &'a (dyn Fn(u32) -> Vec3 + Sync),
    k: &'a PrepareParams,
}

/// How many contacts ahead the loaders fetch.
const PREFETCH_AHEAD: usize = 6;

/// Writes the forces of `lanes`' contacts back (on all cores with the `parallel` feature),
/// then adds them to the bodies' constraint forces (on this thread: bodies are shared).
fn store_lanes<F: FloatW>(
    lanes: &mut Lanes<F>,
    contacts: &mut [SolverContact],
    states: &BodyStates,
    sums: Option<&mut BodyScratch>,
    (h, hs): (Real, Real),
) {
    {
        let shared = Disjoint::new(contacts);
        for_each_chunk(&mut lanes.batches, true, |_, chunk| {
            store::write_chunk(chunk, &shared, h, hs);
        });
    }
    if let Some(scratch) = sums {
        store::add_body_forces(&lanes.batches, contacts, states, scratch);
    }
}

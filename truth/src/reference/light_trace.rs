//! The light pass: photons traced from the emitters in seeded chunks, splatted onto the image through the eye.

use super::*;

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, fast, and good enough for sampling (the light
/// pass's photons, `truth::throughput`'s random rays).
pub(crate) struct SplitMix64(u64);

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub(super) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1) with 24 bits.
    pub(crate) fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / 16_777_216.0)
    }
}

pub(super) fn chunk_seed(seed: u64, emitter: usize, chunk: u64) -> u64 {
    let mut m = SplitMix64(seed);
    let a = m.next_u64() ^ (emitter as u64).wrapping_mul(0xd1b5_4a32_d192_ed03);
    let mut m = SplitMix64(a);
    m.next_u64() ^ chunk.wrapping_mul(0x8cb9_2ba7_2f3d_8dd7)
}

pub(super) struct ChunkResult {
    pub(super) splats: Vec<(usize, Vec3)>,
    /// The chunk's photon beams on the image (empty when the scene has no scattering medium).
    pub(super) beams: Vec<Vec3>,
    pub(super) deposited: Vec<Vec3>,
    pub(super) rays: u64,
    /// Photon path segments among `rays` (the rest are connections to the eye).
    pub(super) segments: u64,
}

/// Chunks traced in parallel before their results are added up in order: bounds the memory of
/// the chunks' beam images (a whole image each).
pub(super) const CHUNKS_PER_BATCH: usize = 32;

/// The light pass. `depths` (view depth of each pixel's first surface, [`view_depths`]) hides
/// photon beams behind surfaces; it is only read when the scene has a scattering medium.
/// `clock` times the connections to the eye and the beams of a profiled render.
pub(super) fn light_trace_with(
    scene: &Scene,
    bvh: &SceneBvh,
    (camera, time, width, height): (&Camera, f32, u32, u32),
    opts: &ReferenceOptions,
    setup: &PhotonSetup,
    depths: &[f32],
    clock: &PartClock,
) -> LightTrace {
    let n_lights = scene.lights.len();
    let pixels = (width * height) as usize;
    let emitters = emitters(scene, time, &setup.targets, opts.photons);
    let mut emitted = vec![Vec3::ZERO; n_lights];
    for e in &emitters {
        emitted[e.light] += scene.lights[e.light].intensity * e.measure;
    }
    let work = work_units(&emitters);
    let media = Media::new(scene, time);
    let medium = scene.medium.as_ref();
    let tracer = Tracer::new(scene, bvh, &media, opts, clock);
    let eye = Eye::new(camera, width, height, &media, medium);
    let beams = medium.map(|m| BeamSplatter::new(m, camera, width, height, depths));
    let trace_chunk = |&(ei, first, count): &(usize, u64, u64)| {
        let e = &emitters[ei];
        let light = &scene.lights[e.light];
        let mut rng = SplitMix64(chunk_seed(opts.seed, ei, first));
        let mut out = ChunkResult {
            splats: Vec::new(),
            beams: if beams.is_some() {
                vec![Vec3::ZERO; pixels]
            } else {
                Vec::new()
            },
            deposited: vec![Vec3::ZERO; n_lights],
            rays: 0,
            segments: 0,
        };
        for _ in 0..count {
            let (u, v) = (rng.next_f32(), rng.next_f32());
            let (from, w) = e.sample(u, v);
            // Balance heuristic over the cones or discs of this light that could draw it.
            let power = photon_power(light, &emitters, ei, from, w);
            let (mut rays, mut eye_rays) = (0, 0);
            let beam_image = &mut out.beams;
            tracer.trace_photon(
                from,
                w,
                power,
                setup.min_specular_bounces,
                &mut rng,
                &mut rays,
                |_hit, s, albedo, dir, p| {
                    out.deposited[e.light] += p;
                    let _timer = clock.timer(Part::Connections);
                    if let Some(splat) = eye.connect(bvh, s, albedo, dir, p, &mut eye_rays) {
                        out.splats.push(splat);
                    }
                },
                |origin, dir, length, p| {
                    if let Some(b) = &beams {
                        let _timer = clock.timer(Part::Beams);
                        b.splat(origin, dir, length, p, beam_image);
                    }
                },
            );
            out.rays += rays + eye_rays;
            out.segments += rays;
        }
        out
    };

    // Ordered reduction, a batch of chunks at a time ([`Sums`]).
    let mut sums = Sums::new(pixels, beams.is_some(), n_lights);
    for batch in work.chunks(CHUNKS_PER_BATCH) {
        let results: Vec<ChunkResult> = batch.par_iter().map(trace_chunk).collect();
        for r in results {
            sums.add(r);
        }
    }
    for (sum, v) in sums.radiance.iter_mut().zip(&sums.beam_radiance) {
        *sum += *v;
    }
    LightTrace {
        radiance: sums.radiance.iter().map(|v| v.as_vec3()).collect(),
        beam_radiance: sums.beam_radiance.iter().map(|v| v.as_vec3()).collect(),
        deposited: sums.deposited,
        emitted,
        photons_traced: emitters.iter().map(|e| e.photons).sum(),
        photons_stored: sums.stored,
        rays: sums.rays,
        segments: sums.segments,
    }
}

/// The light pass's work units: (emitter, first photon, count), chunks of [`PHOTON_CHUNK`]
/// photons in a fixed order.
fn work_units(emitters: &[scene::emission::Emitter]) -> Vec<(usize, u64, u64)> {
    let mut work = Vec::new();
    for (ei, e) in emitters.iter().enumerate() {
        let mut first = 0;
        while first < e.photons {
            work.push((ei, first, PHOTON_CHUNK.min(e.photons - first)));
            first += PHOTON_CHUNK;
        }
    }
    work
}

/// The chunks' results summed in order (see "Determinism"), in f64: a pixel of a bright
/// caustic sums tens of thousands of photons at high counts, and an f32 sum drifts by
/// ~n * 2^-24 of its value (1e-3 at 20 000 photons), which the GPU tracer's convergence study
/// (raytracer/README.md) showed as an error floor.
struct Sums {
    radiance: Vec<DVec3>,
    beam_radiance: Vec<DVec3>,
    deposited: Vec<Vec3>,
    rays: u64,
    segments: u64,
    stored: u64,
}

impl Sums {
    fn new(pixels: usize, beams: bool, lights: usize) -> Self {
        Self {
            radiance: vec![DVec3::ZERO; pixels],
            beam_radiance: vec![DVec3::ZERO; if beams { pixels } else { 0 }],
            deposited: vec![Vec3::ZERO; lights],
            rays: 0,
            segments: 0,
            stored: 0,
        }
    }

    fn add(&mut self, r: ChunkResult) {
        for (i, v) in &r.splats {
            self.radiance[*i] += v.as_dvec3();
        }
        for (sum, v) in self.beam_radiance.iter_mut().zip(&r.beams) {
            *sum += v.as_dvec3();
        }
        self.stored += r.splats.len() as u64;
        for (d, x) in self.deposited.iter_mut().zip(&r.deposited) {
            *d += *x;
        }
        self.rays += r.rays;
        self.segments += r.segments;
    }
}

/// The closest-hit rays the light pass casts for `photons` caustic photons of `scene` at
/// `time`: every segment of every photon path, as [`render`]'s light pass draws them (the same
/// emitters, seeds and random choices), without the visibility rays of the connections to the
/// eye. `truth::throughput` casts them as the light pass's own rays, the reference's main work
/// on the glass scenes.
pub fn photon_rays(
    scene: &Scene,
    time: f32,
    photons: u64,
    opts: &ReferenceOptions,
) -> Vec<(Vec3, Vec3)> {
    let bvh = SceneBvh::build(scene, time);
    let media = Media::new(scene, time);
    let clock = PartClock::new(false);
    let tracer = Tracer::new(scene, &bvh, &media, opts, &clock);
    let setup = PhotonSetup::caustics(scene);
    let emitters = emitters(scene, time, &setup.targets, photons);
    let mut rays = Vec::new();
    for (ei, first, count) in work_units(&emitters) {
        let e = &emitters[ei];
        let light = &scene.lights[e.light];
        let mut rng = SplitMix64(chunk_seed(opts.seed, ei, first));
        for _ in 0..count {
            let (u, v) = (rng.next_f32(), rng.next_f32());
            let (from, w) = e.sample(u, v);
            let power = photon_power(light, &emitters, ei, from, w);
            let record = |o: Vec3, d: Vec3, _: f32, _: Vec3| rays.push((o, d));
            // Every segment from the first (min_bounces 0); the choices are the caustic pass's.
            let land = |_: &Hit, _: &Surface, _: Vec3, _: Vec3, _: Vec3| {};
            tracer.trace_photon(from, w, power, 0, &mut rng, &mut 0, land, record);
        }
    }
    rays
}

impl<'a> Tracer<'a> {
    /// The tracer of `scene` at one time (its BVH and volumes built for it), with the options'
    /// depth bound and the scene's medium: what the eye pass, the light pass and
    /// [`photon_rays`] trace with.
    pub(super) fn new(
        scene: &'a Scene,
        bvh: &'a SceneBvh,
        media: &'a Media,
        opts: &ReferenceOptions,
        clock: &'a PartClock,
    ) -> Self {
        Tracer {
            scene,
            bvh,
            media,
            medium: scene.medium.as_ref(),
            max_depth: opts.max_depth,
            clock,
        }
    }
}

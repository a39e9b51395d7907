/* render.c: tiles traced in parallel into a linear image, with statistics. */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "adaptive.h"
#include "tracer/aov.h"
#include "camera.h"
#include "base/error.h"
#include "image/image.h"
#include "base/interrupt.h"
#include "base/rng.h"
#include "path.h"
#include "shade.h"
#include "base/clock.h"
#include "base/mem.h"
#include "scene/compile.h"
#include "plan.h"
#include "scene/intersect.h"

#define TILE 16

static const char *const ray_names[LC_RAY_KINDS] = {"camera", "shadow", "reflection",
                                                     "glossy", "light", "cut",
                                                     "refraction", "indirect", "ao"};

const char *lc_ray_kind_name(lc_ray_kind k)
{
    return (unsigned)k < LC_RAY_KINDS ? ray_names[k] : "?";
}

const char *lc_need_name(unsigned need)
{
    switch (need) {
    case LC_NEED_SHADOW: return "shadow";
    case LC_NEED_EMITTER: return "emitter";
    case LC_NEED_SPECULAR: return "specular";
    case LC_NEED_REFLECT: return "reflect";
    case LC_NEED_AMBIENT: return "ambient";
    case LC_NEED_GLOSSY: return "glossy";
    case LC_NEED_AREA: return "area";
    case LC_NEED_LENS: return "lens";
    case LC_NEED_REFRACT: return "refract";
    case LC_NEED_FILTER: return "filter";
    case LC_NEED_TEXTURE: return "texture";
    case LC_NEED_SPOT: return "spot";
    case LC_NEED_SUN: return "sun";
    case LC_NEED_SKY: return "sky";
    case LC_NEED_INDIRECT: return "indirect";
    case LC_NEED_AO: return "ao";
    default: return "?";
    }
}

typedef struct {
    const lc_render_options *o;
    lc_scene       *scene;
    camera_frame    cam;
    lc_image       *img;
    int             tiles_x, ntiles;
    pthread_mutex_t lock;
    pthread_cond_t  tile_done;
    int             next, done, cancel, running;
    adaptive       *adaptive;   /* NULL: every pixel takes `samples` */
    int             x0, y0, x1, y1;   /* the pixels of the frame the image holds */
    int             ex0, ey0, ew, eh; /* those traced: the region and a margin */
    uint32_t       *hits;       /* alpha with adaptive or progressive: camera rays
                                ** that hit, per traced pixel, across passes */
    double         *acc;        /* progressive, not adaptive: each traced pixel's sum
                                ** of r, g, b over its samples [0, from) */
    uint32_t        from, to;   /* ... and this pass adds samples [from, to) */
    double          base, share;   /* progress: this pass's start and part of all */
    int             random;     /* some dimension is sampled: pixels need their keys */
    unsigned        aovs;       /* the AOVs asked for (bits 1 << LC_AOV_*) */
    sig_atomic_t    interrupts_seen;   /* lc_interrupt()'s count when the render began */
} job;

typedef struct {
    job      *j;
    tracer    t;
    pthread_t thread;
    aov_count *objects, *materials;   /* AOVs: a pixel's ids, room for each sample */
} worker;

/* A tracer for this render: the switches and counts the compile decided. */
static void tracer_init(tracer *t, lc_scene *s, const lc_render_options *o)
{
    memset(t, 0, sizeof *t);
    t->scene = s;
    t->needs = s->c.needs;
    t->plan = s->c.plan;
    t->shadows = o->shadows;
    t->max_depth = s->c.depth;
    t->cosine = o->cosine;
    t->cutoff = o->cutoff;
    t->light_samples = o->light_samples;
    t->cone_samples = o->cone_samples;
    t->indirect = o->indirect;
    t->roulette = o->roulette;
    t->nee = o->nee;
    t->ao_samples = o->ao_samples;
    t->ao_distance = o->ao_distance;
    if (o->aovs)
        t->needs |= TRACE_AOV;
}

/* Camera sample s of n of pixel (x, y): the pixel centre when the pixel
** takes one sample, else a point of the pixel's set; through the lens when
** the camera has one. With `hits` (a render with alpha), a ray that meets
** nothing brings back nothing, the transparent background, and one that
** meets something counts in *hits: one more cast, only when alpha is asked. */
static radiance camera_sample(const job *j, tracer *t, int x, int y, uint32_t s,
                              uint32_t n, uint32_t *hits)
{
    double u[2] = {0.5, 0.5};
    if (n > 1)
        sample_2d(&t->ps, sample_dim(DIM_PIXEL, 0, 0), s, n, u);
    ray r = camera_ray(&j->cam, x + u[0], y + u[1]);
    if (t->needs & LC_NEED_LENS) {
        sample_2d(&t->ps, sample_dim(DIM_LENS, 0, 0), s, n, u);
        camera_lens(&j->cam, &r, u);
    }
    t->rays[LC_RAY_CAMERA]++;
    if (hits) {
        if (!intersect_occluded(t->scene, &r, HUGE_VAL, &t->counts)) {
            radiance none = {0, 0, 0};
            return none;
        }
        ++*hits;
    }
    /* The integrator: the path tracer for light that bounces, else the seed's. */
    if (t->needs & LC_NEED_INDIRECT)
        return path_ray(t, &r, s, n);
    return shade_ray(t, &r, s, n);
}

/* Writes the mean of n samples; under RADIANCE_CAP, so the float is
** finite (FLT_MAX at most). */
static void put_pixel(lc_image *img, int x, int y, const double sum[3], uint32_t n)
{
    lc_image_set(img, x, y, rgb((float)fmin(sum[0] / n, FLT_MAX),
                                (float)fmin(sum[1] / n, FLT_MAX),
                                (float)fmin(sum[2] / n, FLT_MAX)));
}

/* Pixel (x, y) of the frame, in the image when the region holds it. */
ALWAYS_INLINE void frame_put(job *j, int x, int y, const double sum[3], uint32_t n,
                             uint32_t hits)
{
    if (x < j->x0 || x >= j->x1 || y < j->y0 || y >= j->y1)
        return;                                     /* the margin: traced, not kept */
    put_pixel(j->img, x - j->x0, y - j->y0, sum, n);
    if (j->img->alpha)
        lc_image_set_alpha(j->img, x - j->x0, y - j->y0, (float)hits / (float)n);
}

/* A pass of a progressive render that is not adaptive: every pixel adds
** samples [from, to) of its N to its sum, in the order a plain render adds
** them, into the same double; so after the last pass each pixel holds the
** plain render's sum, bit for bit, divided by the same N. Apart from the
** plain loop below, which stays as it was (B1 measures it). */
NEVER_INLINE void tile_pass(job *j, tracer *t, int x0, int y0, int x1, int y1)
{
    const lc_render_options *o = j->o;
    uint32_t n = (uint32_t)o->samples;
    int alpha = j->img->alpha != NULL;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            uint64_t key = (uint64_t)y * (uint64_t)o->width + (uint64_t)x;
            size_t pixel = (size_t)(y - j->ey0) * j->ew + (size_t)(x - j->ex0);
            if (j->random)
                t->ps = sample_pixel(o->sampler, o->seed, o->frame, key);
            double *sum = j->acc + 3 * pixel;
            uint32_t *hits = alpha ? j->hits + pixel : NULL;
            for (uint32_t s = j->from; s < j->to; s++) {
                radiance c = camera_sample(j, t, x, y, s, n, hits);
                sum[0] += c.r, sum[1] += c.g, sum[2] += c.b;
            }
            t->samples += j->to - j->from;
            frame_put(j, x, y, sum, j->to, hits ? *hits : 0);
        }
}

/* Pixel (x, y) with its AOVs: the samples the plain loop takes, each one's
** record summed beside its radiance. Out of the tile loop, so a render
** without AOVs pays one test per pixel. */
NEVER_INLINE void render_pixel_aovs(job *j, worker *w, int x, int y, uint32_t n, int alpha)
{
    tracer *t = &w->t;
    double sum[3] = {0, 0, 0};
    uint32_t hits = 0;
    aov_pixel p;
    aov_pixel_begin(&p, w->objects, w->materials);
    for (uint32_t s = 0; s < n; s++) {
        aov_sample as;
        memset(&as, 0, sizeof as);
        t->aov = &as;
        radiance c = camera_sample(j, t, x, y, s, n, alpha ? &hits : NULL);
        sum[0] += c.r, sum[1] += c.g, sum[2] += c.b;
        aov_pixel_add(&p, &as, j->cam.o, j->cam.f);
    }
    t->aov = NULL;
    t->samples += n;
    frame_put(j, x, y, sum, n, hits);
    if (x >= j->x0 && x < j->x1 && y >= j->y0 && y < j->y1)
        aov_put(j->img, x - j->x0, y - j->y0, &p, n);
}

static void render_tile(job *j, worker *w, int tile)
{
    tracer *t = &w->t;
    const lc_render_options *o = j->o;
    adaptive *ad = j->adaptive;
    int x0 = j->ex0 + (tile % j->tiles_x) * TILE, y0 = j->ey0 + (tile / j->tiles_x) * TILE;
    int x1 = x0 + TILE < j->ex0 + j->ew ? x0 + TILE : j->ex0 + j->ew;
    int y1 = y0 + TILE < j->ey0 + j->eh ? y0 + TILE : j->ey0 + j->eh;
    if (j->acc) {
        tile_pass(j, t, x0, y0, x1, y1);
        return;
    }
    uint32_t n = (uint32_t)o->samples;
    int alpha = j->img->alpha != NULL;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            /* Keyed by its place in the whole frame: a region's pixel is the
            ** same pixel as in the frame rendered whole. */
            uint64_t key = (uint64_t)y * (uint64_t)o->width + (uint64_t)x;
            size_t pixel = (size_t)(y - j->ey0) * j->ew + (size_t)(x - j->ex0);
            if (ad && !ad->active[pixel])
                continue;
            if (j->random)
                t->ps = sample_pixel(o->sampler, o->seed, o->frame, key);
            if (j->aovs) {
                render_pixel_aovs(j, w, x, y, n, alpha);
                continue;
            }
            if (!ad) {
                double sum[3] = {0, 0, 0};
                uint32_t hits = 0;
                for (uint32_t s = 0; s < n; s++) {
                    radiance c = camera_sample(j, t, x, y, s, n, alpha ? &hits : NULL);
                    sum[0] += c.r, sum[1] += c.g, sum[2] += c.b;
                }
                t->samples += n;
                frame_put(j, x, y, sum, n, hits);
                continue;
            }
            /* Adaptive: on from where the last pass stopped; odd-numbered
            ** samples also go to the half the error is estimated with. */
            double *sum = ad->sum + 6 * pixel;
            uint32_t s = ad->n[pixel], *hits = alpha ? j->hits + pixel : NULL;
            for (; s < ad->target; s++) {
                radiance c = camera_sample(j, t, x, y, s, n, hits);
                sum[0] += c.r, sum[1] += c.g, sum[2] += c.b;
                if (s & 1)
                    sum[3] += c.r, sum[4] += c.g, sum[5] += c.b;
            }
            t->samples += s - ad->n[pixel];
            ad->n[pixel] = s;
            frame_put(j, x, y, sum, s, hits ? *hits : 0);
        }
}

/* Adaptive sampling keeps a pixel going while it or a neighbour is over the
** noise target, so what a pixel takes in pass k depends on pixels k away. A
** region is traced with that many pixels around it (as far as the frame
** goes), so that each of its pixels takes the same samples as in the whole
** frame: the number of passes after the first. */
static int adaptive_margin(const lc_render_options *o)
{
    if (!(o->noise > 0))
        return 0;
    uint32_t max = (uint32_t)o->samples;
    uint32_t target = (uint32_t)o->min_samples + (o->min_samples & 1);
    int passes = 0;
    if (target > max)
        target = max;
    while (target < max) {                   /* as adaptive_next steps it */
        target = target > max / 2 ? max : 2 * target;
        passes++;
    }
    return passes;
}

static lc_status explain_locked(lc_scene *s, const lc_render_options *o, int x, int y,
                                int sample, lc_ray_record **records, size_t *n,
                                lc_error *err)
{
    *records = NULL;
    *n = 0;
    if (lc_render_options_check(o, err))
        return LC_EARG;
    if (x < 0 || x >= o->width || y < 0 || y >= o->height)
        return error_fail(err, LC_EARG, x < 0 || x >= o->width ? "x" : "y",
                       "pixel (%d, %d) is outside the %dx%d image", x + 1, y + 1,
                       o->width, o->height);
    if (sample < 0 || sample >= o->samples)
        return error_fail(err, LC_EARG, "sample", "must be in [1, %d], got %d", o->samples,
                       sample + 1);
    if (!s->has_camera)
        return error_fail(err, LC_EARG, "camera", "the scene has no camera");
    if (plan_scene(s, o, interrupt_count(), err))
        return err ? err->code : LC_ENOMEM;
    job j;
    memset(&j, 0, sizeof j);
    j.o = o;
    camera_frame_init(&s->camera, o->width, o->height, &j.cam);
    ray_log log;
    memset(&log, 0, sizeof log);
    tracer t;
    tracer_init(&t, s, o);
    t.log = &log;
    t.ps = sample_pixel(o->sampler, o->seed, o->frame, (uint64_t)y * o->width + x);
    camera_sample(&j, &t, x, y, (uint32_t)sample, (uint32_t)o->samples, NULL);
    explain_finish(&log);
    explain_free(&log);
    if (log.failed) {
        free(log.r);               /* explain records are plain malloc: the caller frees */
        return error_fail(err, LC_ENOMEM, NULL, "out of memory recording the rays");
    }
    *records = log.r;
    *n = log.n;
    error_ok(err);
    return LC_OK;
}

static void *work(void *arg)
{
    worker *w = arg;
    job *j = w->j;
    int tile = -1;
    /* One lock per tile, and no wake-up of the waiting thread per tile: it
    ** polls progress every 100 ms and only needs waking at the end (a signal
    ** per tile cost B1 context switches worth a few % on two cores). */
    for (;;) {
        pthread_mutex_lock(&j->lock);
        if (tile >= 0)
            j->done++;
        tile = j->cancel || j->next >= j->ntiles ? -1 : j->next++;
        if (tile < 0)
            break;
        pthread_mutex_unlock(&j->lock);
        render_tile(j, w, tile);
    }
    j->running--;
    pthread_cond_signal(&j->tile_done);
    pthread_mutex_unlock(&j->lock);
    return NULL;
}

/* Runs every tile of one pass on the workers (tracers kept across passes)
** while this thread reports progress and honours cancel. Returns the
** number of threads that ran. */
static int run_pass(job *j, worker *ws, int nt)
{
    const lc_render_options *o = j->o;
    j->next = j->done = 0;
    int started = 0;
    for (int i = 0; i < nt; i++) {
        ws[i].j = j;
        pthread_mutex_lock(&j->lock);
        j->running++;
        pthread_mutex_unlock(&j->lock);
        if (pthread_create(&ws[i].thread, NULL, work, &ws[i]) != 0) {
            pthread_mutex_lock(&j->lock);
            j->running--;
            pthread_mutex_unlock(&j->lock);
            break;
        }
        started++;
    }
    if (started == 0) {     /* no thread could start: trace on this one */
        j->running = 1;
        work(&ws[0]);
    }
    /* The calling thread reports progress between tiles and honours cancel. */
    pthread_mutex_lock(&j->lock);
    while (j->running > 0) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 100000000;
        if (until.tv_nsec >= 1000000000) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000;
        }
        pthread_cond_timedwait(&j->tile_done, &j->lock, &until);
        if (interrupt_count() != j->interrupts_seen)
            j->cancel = 1;
        if (o->progress && !j->cancel) {
            double done = j->base + j->share * j->done / j->ntiles;
            pthread_mutex_unlock(&j->lock);
            int stop = o->progress(o->progress_ud, done);
            pthread_mutex_lock(&j->lock);
            if (stop)
                j->cancel = 1;
        }
    }
    /* Once more at the pass's end: workers that finished before the first
    ** wait would otherwise leave the callback never called. */
    if (o->progress && !j->cancel) {
        double done = j->base + j->share * j->done / j->ntiles;
        pthread_mutex_unlock(&j->lock);
        if (o->progress(o->progress_ud, done))
            j->cancel = 1;
        pthread_mutex_lock(&j->lock);
    }
    pthread_mutex_unlock(&j->lock);
    for (int i = 0; i < started; i++)
        pthread_join(ws[i].thread, NULL);
    return started ? started : 1;
}

/* A picture that is likely not what was meant: a scene nothing lights, or
** one whose every pixel came out black. */
static void warn(const lc_scene *s, const lc_image *img, lc_stats *st)
{
    st->warning[0] = '\0';
    if (lc_scene_light_count(s) == 0 && s->nemitters == 0 &&
        c_is_black(s->settings.ambient) && !s->c.sky_lights) {
        snprintf(st->warning, sizeof st->warning, "the scene has no light (no point, "
                 "spot or directional light, no emissive shape, no ambient light): only "
                 "the background shows");
        return;
    }
    size_t n = 3 * (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        if (img->px[i] != 0)
            return;
    snprintf(st->warning, sizeof st->warning, "every pixel is black: the lights reach "
             "nothing the camera sees (check the camera, the lights' positions and "
             "intensities, and the colours)");
}

/* The statistics of the render so far, into st (its passes and stopped
** kept): the workers' counts summed, the scene's figures, the times since
** t0 (the start) and t1 (the end of the compile). */
static void gather(const job *j, const worker *ws, int nt, int threads, double t0,
                   double t1, lc_stats *st)
{
    const lc_scene *s = j->scene;
    int passes = st->passes, stopped = st->stopped;
    memset(st, 0, sizeof *st);
    for (int i = 0; i < nt; i++) {
        for (int k = 0; k < LC_RAY_KINDS; k++)
            st->rays[k] += ws[i].t.rays[k];
        st->self_hits += ws[i].t.self_hits;
        st->samples += ws[i].t.samples;
        st->prim_tests += ws[i].t.counts.prims;
        st->node_tests += ws[i].t.counts.nodes;
        st->csg_tests += ws[i].t.counts.csg;
    }
    if (j->adaptive)
        st->converged = adaptive_converged(j->adaptive);
    double t2 = clock_seconds();
    st->compile_seconds = t1 - t0;
    st->trace_seconds = t2 - t1;
    st->seconds = t2 - t0;
    st->needs = s->c.needs;
    st->bvh_nodes = s->c.bvh.nnodes;
    st->primitives = s->c.ntris;
    for (int k = 0; k < LC_SHAPE_KINDS; k++)
        st->primitives += s->shapes[k].n;
    st->primitives += s->ncsgs;
    st->degenerate = s->c.degenerate;
    memcpy(st->why, s->c.why, sizeof st->why);
    st->threads = threads;
    st->aovs = j->aovs;
    st->passes = passes;
    st->stopped = stopped;
    warn(s, j->img, st);
}

/* The frame's pixels the image holds (the region, or all of it) and those
** traced: the region with adaptive sampling's margin around it. */
static void job_frame(job *j, const lc_render_options *o)
{
    j->x1 = o->width;
    j->y1 = o->height;
    if (o->region[0] | o->region[1] | o->region[2] | o->region[3]) {
        j->x0 = o->region[0];
        j->y0 = o->region[1];
        j->x1 = o->region[2];
        j->y1 = o->region[3];
    }
    int margin = adaptive_margin(o);
    j->ex0 = j->x0 - margin > 0 ? j->x0 - margin : 0;
    j->ey0 = j->y0 - margin > 0 ? j->y0 - margin : 0;
    j->ew = (j->x1 + margin < o->width ? j->x1 + margin : o->width) - j->ex0;
    j->eh = (j->y1 + margin < o->height ? j->y1 + margin : o->height) - j->ey0;
}

/* The image (window, alpha, AOVs) and the per-pixel buffers of adaptive
** and progressive renders, into j; NULL (nothing left allocated) when out
** of memory. */
static lc_image *job_image(job *j, const lc_render_options *o, lc_error *err)
{
    lc_image *img = lc_image_new(j->x1 - j->x0, j->y1 - j->y0, err);
    if (!img)
        return NULL;
    lc_window win = {j->x0, j->y0, o->width, o->height};
    if (lc_image_set_window(img, win, err) || (o->alpha && lc_image_add_alpha(img, err)) ||
        (o->aovs && aov_images_new(img, o->aovs, err))) {
        lc_image_free(img);
        return NULL;
    }
    if (o->alpha && (o->noise > 0 || o->progressive)) {
        j->hits = mem_calloc((size_t)j->ew * j->eh, sizeof *j->hits);
        if (!j->hits) {
            lc_image_free(img);
            error_fail(err, LC_ENOMEM, NULL, "out of memory for the alpha of %dx%d pixels",
                       j->ew, j->eh);
            return NULL;
        }
    }
    if (o->progressive && !(o->noise > 0)) {
        j->acc = mem_calloc((size_t)j->ew * j->eh, 3 * sizeof *j->acc);
        if (!j->acc) {
            mem_free(j->hits);
            lc_image_free(img);
            error_fail(err, LC_ENOMEM, NULL, "out of memory for the sums of a progressive "
                       "render of %dx%d pixels", j->ew, j->eh);
            return NULL;
        }
    }
    return img;
}

/* The number of threads to trace with: o->threads, or one per core, at
** most one per tile. */
static int job_threads(const job *j, const lc_render_options *o)
{
    int nt = o->threads;
    if (nt == 0) {
        long nc = sysconf(_SC_NPROCESSORS_ONLN);
        nt = nc < 1 ? 1 : nc > LC_MAX_THREADS ? LC_MAX_THREADS : (int)nc;
    }
    return nt > j->ntiles ? j->ntiles : nt;
}

static void workers_free(worker *ws, int nt)
{
    for (int i = 0; i < nt; i++)
        mem_free(ws[i].objects), mem_free(ws[i].materials);
    mem_free(ws);
}

/* nt workers, each with its tracer and room for the AOVs' ids; NULL when
** out of memory. */
static worker *workers_new(lc_scene *s, const lc_render_options *o, int nt, lc_error *err)
{
    worker *ws = mem_calloc((size_t)nt, sizeof *ws);
    if (!ws) {
        error_fail(err, LC_ENOMEM, NULL, "out of memory starting %d threads", nt);
        return NULL;
    }
    int room = 1;
    for (int i = 0; i < nt; i++) {
        tracer_init(&ws[i].t, s, o);
        if (o->aovs)
            room &= aov_room((uint32_t)o->samples, &ws[i].objects, &ws[i].materials);
    }
    if (!room) {
        workers_free(ws, nt);
        error_fail(err, LC_ENOMEM, NULL, "out of memory for the AOVs' ids of %d samples",
                   o->samples);
        return NULL;
    }
    return ws;
}

/* Every pass of the render: one, the adaptive passes, or the progressive
** ones (1, 2, 4, ... samples in all, then max), each followed by on_pass;
** the statistics into *sum. t0, t1: the start and the compile's end. */
static void run_passes(job *j, worker *ws, int nt, adaptive *ad, double t0, double t1,
                       lc_stats *sum)
{
    const lc_render_options *o = j->o;
    uint32_t max = (uint32_t)o->samples;
    int npasses = j->adaptive ? adaptive_passes(ad) : 1, threads = 0;
    memset(sum, 0, sizeof *sum);
    j->share = 1;
    for (;;) {
        if (j->acc) {
            /* Progress by samples' worth. */
            j->from = j->to;
            j->to = j->to == 0 ? 1 : j->to > max / 2 ? max : 2 * j->to;
            j->base = (double)j->from / max;
            j->share = (double)(j->to - j->from) / max;
        } else if (j->adaptive) {
            j->share = 1.0 / npasses;             /* adaptive: by passes */
        }
        threads = run_pass(j, ws, nt);
        sum->passes++;
        if (j->cancel)
            break;
        /* adaptive_next only marks the pixels that go on: the image stays. */
        int more = j->adaptive ? adaptive_next(ad) : j->acc && j->to < max;
        if (o->on_pass) {
            gather(j, ws, nt, threads, t0, t1, sum);
            if (o->on_pass(o->on_pass_ud, j->img, sum->passes, sum)) {
                sum->stopped = more;              /* after the last pass: it finished */
                break;
            }
            if (interrupt_count() != j->interrupts_seen) {
                j->cancel = 1;                    /* a Ctrl-C during the callback */
                break;
            }
        }
        if (!more)
            break;
        j->base += j->adaptive ? j->share : 0;
    }
    gather(j, ws, nt, threads, t0, t1, sum);
}

static lc_image *render_locked(lc_scene *s, const lc_render_options *o, lc_stats *st,
                               lc_error *err)
{
    if (lc_render_options_check(o, err))
        return NULL;
    if (!s->has_camera) {
        error_fail(err, LC_EARG, "camera", "the scene has no camera");
        return NULL;
    }
    /* A Ctrl-C from now on cancels: while the BVH is built (which polls),
    ** between tiles, between adaptive passes. */
    sig_atomic_t interrupts_seen = interrupt_count();
    double t0 = clock_seconds();
    if (plan_scene(s, o, interrupts_seen, err))
        return NULL;
    double t1 = clock_seconds();
    job j;
    memset(&j, 0, sizeof j);
    job_frame(&j, o);
    lc_image *img = job_image(&j, o, err);
    if (!img)
        return NULL;
    j.o = o;
    j.scene = s;
    j.img = img;
    j.interrupts_seen = interrupts_seen;
    camera_frame_init(&s->camera, o->width, o->height, &j.cam);
    j.tiles_x = (j.ew + TILE - 1) / TILE;
    j.ntiles = j.tiles_x * ((j.eh + TILE - 1) / TILE);
    j.random = o->samples > 1 ||
               (s->c.needs & (LC_NEED_AREA | LC_NEED_GLOSSY | LC_NEED_LENS |
                              LC_NEED_INDIRECT | LC_NEED_AO)) != 0;
    int nt = job_threads(&j, o);
    adaptive ad;
    worker *ws = workers_new(s, o, nt, err);
    if (!ws || (o->noise > 0 && adaptive_init(&ad, o, j.ew, j.eh, err))) {
        if (ws)
            workers_free(ws, nt);
        mem_free(j.hits);
        mem_free(j.acc);
        lc_image_free(img);
        return NULL;
    }
    j.aovs = o->aovs;
    pthread_mutex_init(&j.lock, NULL);
    pthread_cond_init(&j.tile_done, NULL);
    if (o->noise > 0)
        j.adaptive = &ad;
    lc_stats sum;
    run_passes(&j, ws, nt, &ad, t0, t1, &sum);
    if (j.adaptive)
        adaptive_free(&ad);
    workers_free(ws, nt);
    mem_free(j.hits);
    mem_free(j.acc);
    pthread_mutex_destroy(&j.lock);
    pthread_cond_destroy(&j.tile_done);
    if (st)
        *st = sum;
    if (j.cancel) {
        lc_image_free(img);
        error_fail(err, LC_ECANCEL, NULL, "render cancelled");
        return NULL;
    }
    error_ok(err);
    return img;
}

/* One render (or explain) of a scene at a time: both compile into the
** scene. Two threads that render one scene take turns; different scenes
** render at once, sharing meshes or not. */
lc_image *lc_scene_render(lc_scene *s, const lc_render_options *o, lc_stats *st,
                          lc_error *err)
{
    pthread_mutex_lock(&s->lock);
    lc_image *img = render_locked(s, o, st, err);
    pthread_mutex_unlock(&s->lock);
    return img;
}

lc_status lc_scene_explain(lc_scene *s, const lc_render_options *o, int x, int y,
                           int sample, lc_ray_record **records, size_t *n, lc_error *err)
{
    pthread_mutex_lock(&s->lock);
    lc_status st = explain_locked(s, o, x, y, sample, records, n, err);
    pthread_mutex_unlock(&s->lock);
    return st;
}

/*
 * render.c: the same world-space text scene rendered by Mesa's llvmpipe through OSMesa,
 * as the yardstick for bench llvmpipe. Not part of polypipe and not
 * built by cargo or CI.
 *
 * It reads polypipe's text form (docs/DESIGN.md, "The token stream": a `polypipe 1 world`
 * header, `colour R G B`, vertices `x y z`, NEXT.POLYGON, NEXT.FRAME, END, `#` comments),
 * sets up docs/DESIGN.md's camera and clipping pyramid (eye, at, up; w = z_e·s/d, so the
 * pyramid's vertical half-angle has tangent s/d and its horizontal one a·s/d with a = W/H;
 * hither K1 and yon K2 are GL's near and far planes), and draws every polygon flat in its
 * colour with GL_LESS depth testing, so that at equal depth the earlier polygon wins, as
 * in the Z spec. GL's window depth, (1 − K1/z_e)·K2/(K2 − K1), is the same projective
 * function of z_e that persp writes. Each frame is written to stdout as one binary PPM
 * (P6), rows from the top, like zbuf.
 *
 * Where it differs from polypipe, by design of GL: coverage follows GL's rasterisation
 * rules (a fixed-point sub-pixel grid in llvmpipe, its own edge-ownership convention), so
 * a few pixels along edges may differ; polygons are drawn as triangle fans, which is
 * exact for convex polygons but not the even-odd rule for concave or self-intersecting
 * ones; polygons of fewer than 3 vertices are dropped; depth is 24-bit unless
 * --depth-bits says otherwise.
 *
 * The text parser is hand-written byte scanning over the whole input (mmap for a file),
 * with a fast decimal-to-double conversion (within an ulp or two of correct rounding,
 * far below the float GL keeps), so that the whole-process time measures the renderer,
 * not a slow parser.
 *
 * Usage: render [--size WxH] [--eye X,Y,Z] [--at X,Y,Z] [--up X,Y,Z] [--s S] [--d D]
 *               [--hither K1] [--yon K2] [--depth-bits N] [SCENE | -]
 *        render --renderer    (prints GL_RENDERER and GL_VERSION, renders nothing)
 */
#include <GL/gl.h>
#include <GL/osmesa.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *prog = "llvmpipe-render";

static void die(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", prog);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(1);
}

/* ---- Input: the whole scene in memory, NUL-terminated. ------------------------------- */

typedef struct {
    const char *p;   /* next byte */
    const char *end; /* one past the last byte; *end == '\0' */
    const char *base;
} Scanner;

static char *read_all(int fd, size_t *len)
{
    size_t cap = 1 << 20, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) die("out of memory");
    for (;;) {
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
            if (!buf) die("out of memory");
        }
        ssize_t r = read(fd, buf + n, cap - n);
        if (r < 0) {
            if (errno == EINTR) continue;
            die("reading the scene: %s", strerror(errno));
        }
        if (r == 0) break;
        n += (size_t)r;
    }
    buf[n] = '\0';
    *len = n;
    return buf;
}

/* A regular file is mapped one byte longer than its size: the bytes past the end of
 * the file up to the page boundary read as zero, and when the size is a whole number of
 * pages, an anonymous zero page is mapped after it. Either way *end == '\0'. */
static const char *load(const char *path, size_t *len)
{
    int fd = 0;
    if (path && strcmp(path, "-") != 0) {
        fd = open(path, O_RDONLY);
        if (fd < 0) die("cannot open %s: %s", path, strerror(errno));
    }
    struct stat st;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0) {
        size_t size = (size_t)st.st_size;
        long page = sysconf(_SC_PAGESIZE);
        size_t mapped = (size / page + 1) * page;
        char *m = mmap(NULL, mapped, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m != MAP_FAILED) {
            if (size % page == 0 &&
                mmap(m + size, page, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED, -1, 0) ==
                    MAP_FAILED)
                die("mmap: %s", strerror(errno));
            madvise(m, size, MADV_SEQUENTIAL);
            *len = size;
            if (fd) close(fd);
            return m;
        }
    }
    char *buf = read_all(fd, len);
    if (fd) close(fd);
    return buf;
}

static unsigned line_of(const Scanner *s, const char *at)
{
    unsigned line = 1;
    for (const char *q = s->base; q < at; q++) line += *q == '\n';
    return line;
}

static void die_at(const Scanner *s, const char *at, const char *fmt, const char *word, size_t n)
{
    fprintf(stderr, "%s: line %u: ", prog, line_of(s, at));
    fprintf(stderr, fmt, (int)n, word);
    fputc('\n', stderr);
    exit(1);
}

/* Skips whitespace and comments; returns the start of the next word and its length in
 * *n (0 at the end of the input). */
static const char *next_word(Scanner *s, size_t *n)
{
    const char *p = s->p;
    for (;;) {
        while (*p == ' ' || *p == '\n' || *p == '\t' || *p == '\r') p++;
        if (*p != '#') break;
        while (*p && *p != '\n') p++;
    }
    if (p >= s->end) {
        s->p = s->end;
        *n = 0;
        return s->end;
    }
    const char *w = p;
    while (*p && *p != ' ' && *p != '\n' && *p != '\t' && *p != '\r' && *p != '#') p++;
    /* a stray NUL inside the input is not whitespace: keep it in the word */
    while (p < s->end && *p == '\0') {
        p++;
        while (*p && *p != ' ' && *p != '\n' && *p != '\t' && *p != '\r' && *p != '#') p++;
    }
    s->p = p;
    *n = (size_t)(p - w);
    return w;
}

static int word_is(const char *w, size_t n, const char *kw)
{
    size_t k = strlen(kw);
    return n == k && memcmp(w, kw, k) == 0;
}

static const double pow10_pos[] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

/* Parses a decimal number filling the whole word w[0..n). The fast path: up to 19
 * significant digits into an integer, then one multiply or divide by an exact power of
 * ten (≤ 1e22). Anything else (more digits, large exponents, inf/nan, hex) goes to
 * strtod. Returns 0 when the word is not a finite number. */
static int parse_number(const char *w, size_t n, double *out)
{
    const char *p = w, *end = w + n;
    int neg = 0;
    if (p < end && (*p == '-' || *p == '+')) neg = *p++ == '-';
    uint64_t mant = 0;
    int digits = 0, frac_digits = 0, any = 0, dropped = 0;
    while (p < end && (unsigned)(*p - '0') < 10) {
        if (digits < 19) {
            mant = mant * 10 + (uint64_t)(*p - '0');
            if (mant) digits++;
        } else {
            dropped++;
        }
        p++;
        any = 1;
    }
    if (p < end && *p == '.') {
        p++;
        while (p < end && (unsigned)(*p - '0') < 10) {
            if (digits < 19) {
                mant = mant * 10 + (uint64_t)(*p - '0');
                if (mant) digits++;
                frac_digits++;
            }
            p++;
            any = 1;
        }
    }
    if (!any) goto slow;
    int exp10 = dropped - frac_digits;
    if (p < end && (*p == 'e' || *p == 'E')) {
        p++;
        int eneg = 0, e = 0, edigits = 0;
        if (p < end && (*p == '-' || *p == '+')) eneg = *p++ == '-';
        while (p < end && (unsigned)(*p - '0') < 10) {
            if (e < 100000) e = e * 10 + (*p - '0');
            p++;
            edigits++;
        }
        if (!edigits) return 0;
        exp10 += eneg ? -e : e;
    }
    if (p != end) goto slow;
    if (dropped == 0 && exp10 >= -22 && exp10 <= 22) {
        double v = (double)mant;
        v = exp10 < 0 ? v / pow10_pos[-exp10] : v * pow10_pos[exp10];
        *out = neg ? -v : v;
        return 1;
    }
slow:;
    char tmp[128];
    if (n >= sizeof tmp) return 0;
    memcpy(tmp, w, n);
    tmp[n] = '\0';
    char *e;
    double v = strtod(tmp, &e);
    if (e != tmp + n || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

static unsigned parse_byte(const Scanner *s, const char *w, size_t n)
{
    unsigned v = 0;
    if (n == 0 || n > 3) die_at(s, w, "expected a colour component 0..255, found '%.*s'", w, n);
    for (size_t i = 0; i < n; i++) {
        unsigned d = (unsigned)(w[i] - '0');
        if (d > 9) die_at(s, w, "expected a colour component 0..255, found '%.*s'", w, n);
        v = v * 10 + d;
    }
    if (v > 255) die_at(s, w, "expected a colour component 0..255, found '%.*s'", w, n);
    return v;
}

/* ---- Drawing: polygons batched as triangle fans, drawn in input order. --------------- */

enum { BATCH_VERTICES = 1 << 16 };

typedef struct {
    float *pos;       /* 3 per vertex */
    uint8_t *col;     /* 4 per vertex */
    GLuint *idx;      /* 3 per triangle */
    size_t nv, ni;    /* vertices and indices in the batch */
    size_t cap_v, cap_i;
} Batch;

static void batch_grow(Batch *b, size_t nv, size_t ni)
{
    if (nv > b->cap_v) {
        while (b->cap_v < nv) b->cap_v = b->cap_v ? b->cap_v * 2 : 4096;
        b->pos = realloc(b->pos, b->cap_v * 3 * sizeof(float));
        b->col = realloc(b->col, b->cap_v * 4);
        if (!b->pos || !b->col) die("out of memory");
    }
    if (ni > b->cap_i) {
        while (b->cap_i < ni) b->cap_i = b->cap_i ? b->cap_i * 2 : 4096;
        b->idx = realloc(b->idx, b->cap_i * sizeof(GLuint));
        if (!b->idx) die("out of memory");
    }
}

static void batch_flush(Batch *b)
{
    if (b->ni) {
        glVertexPointer(3, GL_FLOAT, 0, b->pos);
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, b->col);
        glDrawElements(GL_TRIANGLES, (GLsizei)b->ni, GL_UNSIGNED_INT, b->idx);
    }
    b->nv = b->ni = 0;
}

/* Closes the polygon whose vertices are b->pos[first..nv): a fan from its first vertex,
 * or nothing when it has fewer than 3 vertices. */
static void polygon_end(Batch *b, size_t first, const uint8_t rgb[3])
{
    size_t n = b->nv - first;
    if (n < 3) {
        b->nv = first;
        return;
    }
    batch_grow(b, b->nv, b->ni + 3 * (n - 2));
    for (size_t i = first; i < b->nv; i++) {
        uint8_t *c = b->col + 4 * i;
        c[0] = rgb[0], c[1] = rgb[1], c[2] = rgb[2], c[3] = 255;
    }
    GLuint *ix = b->idx + b->ni;
    for (size_t i = 1; i + 1 < n; i++) {
        *ix++ = (GLuint)first;
        *ix++ = (GLuint)(first + i);
        *ix++ = (GLuint)(first + i + 1);
    }
    b->ni += 3 * (n - 2);
}

/* ---- Camera: docs/DESIGN.md's conventions as GL matrices. ----------------------------------- */

typedef struct {
    double eye[3], at[3], up[3], s, d, hither, yon;
} Camera;

static void parse_triple(const char *opt, const char *arg, double v[3])
{
    char *e;
    const char *p = arg;
    for (int i = 0; i < 3; i++) {
        v[i] = strtod(p, &e);
        if (e == p || !isfinite(v[i]) || (i < 2 ? *e != ',' : *e != '\0'))
            die("%s needs X,Y,Z, not '%s'", opt, arg);
        p = e + 1;
    }
}

static double parse_positive(const char *opt, const char *arg)
{
    char *e;
    double v = strtod(arg, &e);
    if (e == arg || *e || !isfinite(v) || v <= 0) die("%s needs a positive number, not '%s'", opt, arg);
    return v;
}

/* The view matrix: f = normalize(at − eye), x = normalize(f × up), y = x × f (docs/DESIGN.md).
 * GL's eye space looks down −z, so its rows are x, y, −f: the same x_e and y_e as
 * polypipe's, and GL's −z_eye is polypipe's z_e. */
static void load_camera(const Camera *c, int W, int H)
{
    double f[3] = {c->at[0] - c->eye[0], c->at[1] - c->eye[1], c->at[2] - c->eye[2]};
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    if (!(fl > 0)) die("the eye and the point looked at must differ");
    for (int i = 0; i < 3; i++) f[i] /= fl;
    double x[3] = {f[1] * c->up[2] - f[2] * c->up[1], f[2] * c->up[0] - f[0] * c->up[2],
                   f[0] * c->up[1] - f[1] * c->up[0]};
    double xl = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    if (!(xl > 0)) die("the up vector must not be parallel to the view direction");
    for (int i = 0; i < 3; i++) x[i] /= xl;
    double y[3] = {x[1] * f[2] - x[2] * f[1], x[2] * f[0] - x[0] * f[2], x[0] * f[1] - x[1] * f[0]};
    const double *rows[3] = {x, y, f};
    double m[16]; /* column-major */
    for (int r = 0; r < 3; r++) {
        double sign = r == 2 ? -1.0 : 1.0;
        const double *a = rows[r];
        m[0 + r] = sign * a[0];
        m[4 + r] = sign * a[1];
        m[8 + r] = sign * a[2];
        m[12 + r] = -sign * (a[0] * c->eye[0] + a[1] * c->eye[1] + a[2] * c->eye[2]);
    }
    m[3] = m[7] = m[11] = 0, m[15] = 1;

    /* The pyramid |y_e| ≤ z_e·s/d, |x_e| ≤ a·z_e·s/d, K1 ≤ z_e ≤ K2, cut at the near plane. */
    double a = (double)W / H, t = c->hither * c->s / c->d;
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-a * t, a * t, -t, t, c->hither, c->yon);
    /* polypipe's device Y runs down (Y = (1 − y_s)·H/2, row 0 at the top); GL's window
     * y runs up. Mirroring y here makes GL's row 0 polypipe's row 0, so glReadPixels
     * returns the rows in PPM order and no copy is needed to flip them. (Measured: the
     * same agreement with zspec as flipping the rows after reading.) */
    glScaled(1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(m);
}

/* ---- Output: one P6 per frame, top row first. ---------------------------------------- */

static void write_all(const void *buf, size_t n)
{
    const char *p = buf;
    while (n) {
        ssize_t w = write(1, p, n);
        if (w < 0) {
            if (errno == EINTR) continue;
            die("writing the frame: %s", strerror(errno));
        }
        p += w;
        n -= (size_t)w;
    }
}

/* The rows come back top first (load_camera mirrors y), straight after the header. */
static void write_frame(int W, int H, uint8_t *ppm, size_t header)
{
    glReadPixels(0, 0, W, H, GL_RGB, GL_UNSIGNED_BYTE, ppm + header);
    write_all(ppm, header + (size_t)W * 3 * H);
}

static void usage(FILE *to)
{
    fprintf(to,
            "Usage: render [OPTIONS] [SCENE]\n"
            "Renders a polypipe world-space text scene (SCENE, or stdin for `-` or none) with\n"
            "Mesa's llvmpipe through OSMesa and writes one binary PPM (P6) per frame.\n"
            "Options: --size WxH (500x500)  --eye X,Y,Z (0,0,20)  --at X,Y,Z (0,0,0)\n"
            "         --up X,Y,Z (0,1,0)  --s S (10)  --d D (16)  --hither K1 (1)  --yon K2 (30)\n"
            "         --depth-bits N (24)\n"
            "       render --renderer   prints GL_RENDERER and GL_VERSION\n");
}

int main(int argc, char **argv)
{
    int W = 500, H = 500, depth_bits = 24;
    Camera cam = {{0, 0, 20}, {0, 0, 0}, {0, 1, 0}, 10, 16, 1, 30};
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i];
        if (!strcmp(o, "-h") || !strcmp(o, "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(o, "--renderer")) {
            static uint8_t px[4];
            OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
            if (!ctx || !OSMesaMakeCurrent(ctx, px, GL_UNSIGNED_BYTE, 1, 1)) die("no OSMesa context");
            printf("%s, OpenGL %s\n", (const char *)glGetString(GL_RENDERER),
                   (const char *)glGetString(GL_VERSION));
            OSMesaDestroyContext(ctx);
            return 0;
        }
        if (o[0] == '-' && o[1] == '-') {
            if (i + 1 >= argc) die("%s needs a value", o);
            const char *v = argv[++i];
            if (!strcmp(o, "--size")) {
                char *e;
                long w = strtol(v, &e, 10), h;
                if (e == v || (*e != 'x' && *e != 'X')) die("--size needs WxH, not '%s'", v);
                const char *hv = e + 1;
                h = strtol(hv, &e, 10);
                if (e == hv || *e || w < 1 || h < 1 || w > 16384 || h > 16384)
                    die("--size needs WxH, not '%s'", v);
                W = (int)w, H = (int)h;
            } else if (!strcmp(o, "--eye")) parse_triple(o, v, cam.eye);
            else if (!strcmp(o, "--at")) parse_triple(o, v, cam.at);
            else if (!strcmp(o, "--up")) parse_triple(o, v, cam.up);
            else if (!strcmp(o, "--s")) cam.s = parse_positive(o, v);
            else if (!strcmp(o, "--d")) cam.d = parse_positive(o, v);
            else if (!strcmp(o, "--hither")) cam.hither = parse_positive(o, v);
            else if (!strcmp(o, "--yon")) cam.yon = parse_positive(o, v);
            else if (!strcmp(o, "--depth-bits")) {
                depth_bits = atoi(v);
                if (depth_bits != 16 && depth_bits != 24 && depth_bits != 32)
                    die("--depth-bits must be 16, 24 or 32");
            } else die("unknown option %s (try --help)", o);
        } else if (path) {
            die("more than one SCENE");
        } else {
            path = o;
        }
    }
    if (!(cam.hither < cam.yon)) die("hither must be nearer than yon");

    size_t len;
    const char *text = load(path, &len);
    Scanner sc = {text, text + len, text};

    size_t n;
    const char *w = next_word(&sc, &n);
    if (!word_is(w, n, "polypipe")) die_at(&sc, w, "expected the header 'polypipe 1 world', found '%.*s'", w, n);
    w = next_word(&sc, &n);
    if (!word_is(w, n, "1")) die_at(&sc, w, "unsupported stream version '%.*s'", w, n);
    w = next_word(&sc, &n);
    if (!word_is(w, n, "world")) die_at(&sc, w, "expected a world-space scene, found '%.*s'", w, n);

    uint8_t *buffer = malloc((size_t)W * H * 4);
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, depth_bits, 0, 0, NULL);
    if (!ctx) die("OSMesaCreateContextExt failed");
    if (!buffer || !OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, W, H)) die("OSMesaMakeCurrent failed");

    glViewport(0, 0, W, H);
    glDisable(GL_DITHER);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glShadeModel(GL_FLAT);
    glClearColor(0, 0, 0, 1);
    glClearDepth(1.0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    load_camera(&cam, W, H);

    char header[64];
    size_t hlen = (size_t)snprintf(header, sizeof header, "P6\n%d %d\n255\n", W, H);
    uint8_t *ppm = malloc(hlen + (size_t)W * H * 3);
    if (!ppm) die("out of memory");
    memcpy(ppm, header, hlen);

    Batch b = {0};
    batch_grow(&b, BATCH_VERTICES + 64, 3 * BATCH_VERTICES);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    /* The grammar: movie ::= frame { NEXT.FRAME frame } END;
     * frame ::= [ polygon { NEXT.POLYGON polygon } ]; polygon ::= colour { vertex }. */
    int in_polygon = 0, want_polygon = 0; /* want_polygon: after NEXT.POLYGON */
    size_t first = 0;
    uint8_t rgb[3] = {0, 0, 0};
    for (;;) {
        w = next_word(&sc, &n);
        if (n == 0) die_at(&sc, w, "the scene ends without END%.*s", "", 0);
        char c = w[0];
        if (c == 'c' && word_is(w, n, "colour")) {
            if (in_polygon) die_at(&sc, w, "expected a vertex, NEXT.POLYGON, NEXT.FRAME or END, found '%.*s'", w, n);
            for (int k = 0; k < 3; k++) {
                const char *cw = next_word(&sc, &n);
                rgb[k] = (uint8_t)parse_byte(&sc, cw, n);
            }
            if (b.nv >= BATCH_VERTICES) batch_flush(&b);
            first = b.nv;
            in_polygon = 1, want_polygon = 0;
            continue;
        }
        if (c == 'N' || c == 'E') {
            int next_polygon = word_is(w, n, "NEXT.POLYGON");
            int next_frame = !next_polygon && word_is(w, n, "NEXT.FRAME");
            int end = !next_polygon && !next_frame && word_is(w, n, "END");
            if (next_polygon || next_frame || end) {
                if (want_polygon) die_at(&sc, w, "expected 'colour' after NEXT.POLYGON, found '%.*s'", w, n);
                if (next_polygon && !in_polygon)
                    die_at(&sc, w, "NEXT.POLYGON with no polygon before it%.*s", "", 0);
                if (in_polygon) polygon_end(&b, first, rgb);
                in_polygon = 0;
                if (next_polygon) {
                    want_polygon = 1;
                    continue;
                }
                batch_flush(&b);
                write_frame(W, H, ppm, hlen);
                if (end) break;
                glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                continue;
            }
        }
        if (!in_polygon) die_at(&sc, w, "expected 'colour', NEXT.FRAME or END, found '%.*s'", w, n);
        double v[3];
        const char *vw = w;
        size_t vn = n;
        for (int k = 0;;) {
            if (!parse_number(vw, vn, &v[k]))
                die_at(&sc, vw, "expected a finite number (x y z of a vertex), found '%.*s'", vw, vn);
            if (++k == 3) break;
            vw = next_word(&sc, &vn);
        }
        batch_grow(&b, b.nv + 1, 0);
        float *q = b.pos + 3 * b.nv++;
        q[0] = (float)v[0], q[1] = (float)v[1], q[2] = (float)v[2];
    }
    w = next_word(&sc, &n);
    if (n) die_at(&sc, w, "unexpected '%.*s' after END", w, n);
    GLenum err = glGetError();
    if (err != GL_NO_ERROR) die("GL error 0x%x", err);
    OSMesaDestroyContext(ctx);
    return 0;
}

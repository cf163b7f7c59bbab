/* A plain C importer of an FMI 2.0 Co-Simulation FMU, the same source for Linux (dlopen) and
 * Windows (LoadLibrary/GetProcAddress; built with mingw-w64, run under wine in the tests).
 *
 *   fmi2_harness LIBRARY RESOURCE_URI SCRIPT OUTPUT
 *
 * SCRIPT is a list of commands, one per line (written by tests/python/test_fmu_win64.py from the
 * modelDescription; numbers as 16 hex digits of their IEEE-754 bits, so nothing is lost or
 * rounded by either C library's printf/strtod):
 *
 *   guid GUID                    instantiate NAME   (fmi2Instantiate, logging on)
 *   real VR BITS | integer VR N | boolean VR 0|1 | string VR TEXT   (fmi2Set*; "\n" in TEXT is a newline)
 *   init                         fmi2SetupExperiment(0) + Enter/ExitInitializationMode
 *   record r:VR i:VR b:VR ...    the outputs written after every step
 *   steps N H_BITS               N fmi2DoStep of h, t = k*h; one line per step
 *   until VR MAX H_BITS          fmi2DoStep of h until Boolean VR is true (at most MAX steps)
 *   reset | terminate | free
 *
 * OUTPUT gets, in order, every call's status ("call NAME STATUS"), every logger message ("log
 * STATUS CATEGORY MESSAGE", formatted by vsnprintf as an importer does) and every recorded step
 * ("step K" and the values as hex bits). Equal files from two platforms mean bit-identical runs. */
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
typedef HMODULE lib_t;
static lib_t lib_open(const char *p) { return LoadLibraryA(p); }
static void *lib_sym(lib_t l, const char *n) { return (void *)GetProcAddress(l, n); }
#else
#include <dlfcn.h>
typedef void *lib_t;
static lib_t lib_open(const char *p) { return dlopen(p, RTLD_NOW | RTLD_LOCAL); }
static void *lib_sym(lib_t l, const char *n) { return dlsym(l, n); }
#endif

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef int fmi2Status;
typedef void (*logger_t)(void *, const char *, fmi2Status, const char *, const char *, ...);
typedef struct {
    logger_t logger;
    void *(*allocate)(size_t, size_t);
    void (*free_memory)(void *);
    void (*step_finished)(void *, fmi2Status);
    void *env;
} callbacks_t;

static FILE *out;

static void logger(void *env, const char *name, fmi2Status status, const char *category,
                   const char *message, ...) {
    char text[4096];
    va_list args;
    (void)env;
    (void)name;
    va_start(args, message);
    vsnprintf(text, sizeof text, message, args);
    va_end(args);
    for (char *c = text; *c; c++)
        if (*c == '\n' || *c == '\r') *c = ' ';
    fprintf(out, "log %d %s %s\n", status, category ? category : "", text);
}

static void *sym(lib_t l, const char *name) {
    void *f = lib_sym(l, name);
    if (!f) {
        fprintf(stderr, "fmi2_harness: %s not exported\n", name);
        exit(2);
    }
    return f;
}

static double bits_to_double(const char *hex) {
    uint64_t u = strtoull(hex, NULL, 16);
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static void put_double(double x) {
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    fprintf(out, " %016" PRIx64, u);
}

#define MAX_RECORD 256

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: fmi2_harness LIBRARY RESOURCE_URI SCRIPT OUTPUT\n");
        return 2;
    }
    lib_t lib = lib_open(argv[1]);
    if (!lib) {
        fprintf(stderr, "fmi2_harness: cannot load %s\n", argv[1]);
        return 2;
    }
    FILE *script = fopen(argv[3], "rb");
    out = fopen(argv[4], "wb");
    if (!script || !out) {
        fprintf(stderr, "fmi2_harness: cannot open %s or %s\n", argv[3], argv[4]);
        return 2;
    }
    fmi2Component (*instantiate)(const char *, int, const char *, const char *, const callbacks_t *, int, int) =
        sym(lib, "fmi2Instantiate");
    fmi2Status (*setup)(fmi2Component, int, double, double, int, double) = sym(lib, "fmi2SetupExperiment");
    fmi2Status (*enter)(fmi2Component) = sym(lib, "fmi2EnterInitializationMode");
    fmi2Status (*exit_init)(fmi2Component) = sym(lib, "fmi2ExitInitializationMode");
    fmi2Status (*set_real)(fmi2Component, const fmi2ValueReference *, size_t, const double *) = sym(lib, "fmi2SetReal");
    fmi2Status (*set_int)(fmi2Component, const fmi2ValueReference *, size_t, const int *) = sym(lib, "fmi2SetInteger");
    fmi2Status (*set_bool)(fmi2Component, const fmi2ValueReference *, size_t, const int *) = sym(lib, "fmi2SetBoolean");
    fmi2Status (*set_string)(fmi2Component, const fmi2ValueReference *, size_t, const char *const *) =
        sym(lib, "fmi2SetString");
    fmi2Status (*get_real)(fmi2Component, const fmi2ValueReference *, size_t, double *) = sym(lib, "fmi2GetReal");
    fmi2Status (*get_int)(fmi2Component, const fmi2ValueReference *, size_t, int *) = sym(lib, "fmi2GetInteger");
    fmi2Status (*get_bool)(fmi2Component, const fmi2ValueReference *, size_t, int *) = sym(lib, "fmi2GetBoolean");
    fmi2Status (*do_step)(fmi2Component, double, double, int) = sym(lib, "fmi2DoStep");
    fmi2Status (*reset)(fmi2Component) = sym(lib, "fmi2Reset");
    fmi2Status (*terminate)(fmi2Component) = sym(lib, "fmi2Terminate");
    void (*free_instance)(fmi2Component) = sym(lib, "fmi2FreeInstance");
    const char *(*types_platform)(void) = sym(lib, "fmi2GetTypesPlatform");
    const char *(*version)(void) = sym(lib, "fmi2GetVersion");

    callbacks_t cb = {logger, calloc, free, NULL, NULL};
    static char line[1 << 16], raw[1 << 16], guid[128] = "";
    char kinds[MAX_RECORD];
    fmi2ValueReference record[MAX_RECORD];
    int n_record = 0;
    fmi2Component c = NULL;
    double t = 0.0;
    long k = 0;
    fprintf(out, "types %s version %s\n", types_platform(), version());

    while (fgets(line, sizeof line, script)) {
        line[strcspn(line, "\r\n")] = 0;
        memcpy(raw, line, sizeof raw);
        char cmd[32] = "";
        int used = 0;
        if (sscanf(line, "%31s %n", cmd, &used) < 1) continue;
        char *arg = line + used;
        fmi2Status st = 0;
        if (!strcmp(cmd, "guid")) {
            snprintf(guid, sizeof guid, "%s", arg);
            continue;
        } else if (!strcmp(cmd, "instantiate")) {
            c = instantiate(arg, 1 /* fmi2CoSimulation */, guid, argv[2], &cb, 0, 1);
            fprintf(out, "call instantiate %s\n", c ? "ok" : "NULL");
            if (!c) return 1;
            t = 0.0;
            k = 0;
            continue;
        } else if (!strcmp(cmd, "real") || !strcmp(cmd, "integer") || !strcmp(cmd, "boolean")) {
            fmi2ValueReference vr = (fmi2ValueReference)strtoul(arg, &arg, 10);
            while (*arg == ' ') arg++;
            if (cmd[0] == 'r') {
                double x = bits_to_double(arg);
                st = set_real(c, &vr, 1, &x);
            } else {
                int n = atoi(arg);
                st = cmd[0] == 'i' ? set_int(c, &vr, 1, &n) : set_bool(c, &vr, 1, &n);
            }
        } else if (!strcmp(cmd, "string")) {
            fmi2ValueReference vr = (fmi2ValueReference)strtoul(arg, &arg, 10);
            if (*arg == ' ') arg++;
            char *w = arg;
            for (char *r = arg; *r; r++) {
                /* The script writes a backslash as two and a newline as backslash-n, so
                   that a Windows path such as Z:\tmp\nc survives. */
                if (r[0] == '\\' && (r[1] == 'n' || r[1] == '\\')) {
                    *w++ = r[1] == 'n' ? '\n' : '\\';
                    r++;
                } else {
                    *w++ = *r;
                }
            }
            *w = 0;
            const char *s = arg;
            st = set_string(c, &vr, 1, &s);
        } else if (!strcmp(cmd, "init")) {
            st = setup(c, 0, 0.0, 0.0, 0, 0.0);
            if (st == 0) st = enter(c);
            if (st == 0) st = exit_init(c);
        } else if (!strcmp(cmd, "record")) {
            n_record = 0;
            for (char *tok = strtok(arg, " "); tok && n_record < MAX_RECORD; tok = strtok(NULL, " ")) {
                kinds[n_record] = tok[0];
                record[n_record++] = (fmi2ValueReference)strtoul(tok + 2, NULL, 10);
            }
            continue;
        } else if (!strcmp(cmd, "steps") || !strcmp(cmd, "until")) {
            long n = 0, max = 0;
            fmi2ValueReference until = 0;
            char hbits[32] = "";
            if (cmd[0] == 's') {
                sscanf(arg, "%ld %31s", &n, hbits);
                max = n;
            } else {
                sscanf(arg, "%u %ld %31s", &until, &max, hbits);
            }
            double h = bits_to_double(hbits);
            for (long i = 0; i < max; i++) {
                st = do_step(c, t, h, 1);
                if (st != 0) break;
                k++;
                t = (double)k * h;
                fprintf(out, "step %ld", k);
                for (int j = 0; j < n_record; j++) {
                    if (kinds[j] == 'r') {
                        double x = 0;
                        get_real(c, &record[j], 1, &x);
                        put_double(x);
                    } else {
                        int v = 0;
                        (kinds[j] == 'i' ? get_int : get_bool)(c, &record[j], 1, &v);
                        fprintf(out, " %d", v);
                    }
                }
                fputc('\n', out);
                if (cmd[0] == 'u') {
                    int done = 0;
                    get_bool(c, &until, 1, &done);
                    if (done) break;
                }
            }
        } else if (!strcmp(cmd, "reset")) {
            st = reset(c);
        } else if (!strcmp(cmd, "terminate")) {
            st = terminate(c);
        } else if (!strcmp(cmd, "free")) {
            free_instance(c);
            c = NULL;
            fprintf(out, "call free\n");
            continue;
        } else {
            fprintf(stderr, "fmi2_harness: unknown command '%s'\n", cmd);
            return 2;
        }
        fprintf(out, "call %s %d\n", raw, st);
    }
    fclose(out);
    return 0;
}

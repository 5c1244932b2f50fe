/* cli_render.c — `fracterra render IN -o OUT`: shaded relief, colour relief, or the 1988 report's profile plot of
 * any heightfield the library can read. */
#include "cli.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static void render_help(void)
{
    printf("Usage: fracterra render IN -o OUT [options]\n"
           "\n"
           "Draws a heightfield (IN: .png .pgm .npy .f32 .obj .ply, as fracterra writes them; foreign PNG/PGM/NPY\n"
           "files are read as raw sample values).\n"
           "\n"
           "  --style S           hillshade (default) | color | profiles\n"
           "  -o, --output OUT    .png; profiles also .svg or .pdf (vectors, for publication)\n"
           "\n"
           "hillshade, color (Horn's method, as gdaldem hillshade -compute_edges: 1 + 254 cos(incidence)):\n"
           "  --azimuth A         light from A degrees clockwise from north (default 315)\n"
           "  --altitude A        light A degrees above the horizon (default 45)\n"
           "  --z-factor Z|auto   vertical exaggeration (default auto: RMS slope of 25 degrees)\n"
           "  --spacing D[,DY]    distance between columns (and rows) in height units (default: as recorded\n"
           "                      in IN, else 1)\n"
           "  color blends a hypsometric colour ramp over [min, max] with the shading (RGB PNG).\n"
           "\n"
           "profiles (the 1988 report's orthographic profile plot, hidden lines removed):\n"
           "  --every K           draw every K-th row, from the front (last) row back (default 8)\n"
           "  --dilation F|auto   vertical dilation z = F * height, in grid spacings; negative inverts peaks\n"
           "                      and valleys (default auto: relief spans 1/10 of the plot width)\n"
           "  --tilt T            v = T (0.25 y + 1.5 z), u = 1.5 x + 0.25 y (default 1)\n"
           "  --base T            a solid base (the report's stratum) T z-units below the lowest point\n"
           "  --width W           picture width in pixels or points (default 1200)\n"
           "  --line-width W      in pixels or points (default 1)\n"
           "\n"
           "  -q, --quiet         no progress and no summary line\n"
           "  -h, --help          this text\n"
           "\n"
           "The output appears only when complete; a failure never replaces an existing file.\n");
}

enum style { STYLE_HILLSHADE, STYLE_COLOR, STYLE_PROFILES };

/* Parses "auto" (-> 0, the library's automatic value) or a number; `nonzero`: 0 itself is refused. */
static bool parse_auto(const char *s, double *out)
{
    if (strcmp(s, "auto") == 0) {
        *out = 0.0;
        return true;
    }
    return frt_parse_double(s, out) && *out != 0.0;
}

int frt_cmd_render(int argc, char **argv)
{
    frt_cli_command = "fracterra render";
    enum {
        OPT_STYLE = 256,
        OPT_AZIMUTH,
        OPT_ALTITUDE,
        OPT_ZFACTOR,
        OPT_SPACING,
        OPT_EVERY,
        OPT_DILATION,
        OPT_TILT,
        OPT_BASE,
        OPT_WIDTH,
        OPT_LINE_WIDTH
    };
    static const struct option opts[] = {{"style", required_argument, 0, OPT_STYLE},
                                         {"azimuth", required_argument, 0, OPT_AZIMUTH},
                                         {"altitude", required_argument, 0, OPT_ALTITUDE},
                                         {"z-factor", required_argument, 0, OPT_ZFACTOR},
                                         {"spacing", required_argument, 0, OPT_SPACING},
                                         {"every", required_argument, 0, OPT_EVERY},
                                         {"dilation", required_argument, 0, OPT_DILATION},
                                         {"tilt", required_argument, 0, OPT_TILT},
                                         {"base", required_argument, 0, OPT_BASE},
                                         {"width", required_argument, 0, OPT_WIDTH},
                                         {"line-width", required_argument, 0, OPT_LINE_WIDTH},
                                         {"output", required_argument, 0, 'o'},
                                         {"quiet", no_argument, 0, 'q'},
                                         {"help", no_argument, 0, 'h'},
                                         {0, 0, 0, 0}};
    frt_hillshade_desc hd;
    memset(&hd, 0, sizeof hd);
    frt_profiles_desc pd;
    memset(&pd, 0, sizeof pd);
    enum style style = STYLE_HILLSHADE;
    const char *output = NULL, *input = NULL;
    bool quiet = false, have_spacing = false, shade_opts = false, profile_opts = false;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        switch (c) {
        case OPT_STYLE:
            if (strcmp(optarg, "hillshade") == 0)
                style = STYLE_HILLSHADE;
            else if (strcmp(optarg, "color") == 0 || strcmp(optarg, "colour") == 0)
                style = STYLE_COLOR;
            else if (strcmp(optarg, "profiles") == 0)
                style = STYLE_PROFILES;
            else
                return frt_cli_fail(FRT_EXIT_USAGE, "--style must be hillshade, color or profiles, got '%s'", optarg);
            break;
        case OPT_AZIMUTH:
            if (!frt_parse_double(optarg, &hd.azimuth) || hd.azimuth < 0.0 || hd.azimuth > 360.0)
                return frt_cli_fail(FRT_EXIT_USAGE, "--azimuth must be 0..360 degrees, got '%s'", optarg);
            if (hd.azimuth == 0.0)
                hd.azimuth = 360.0; /* north; 0 would mean the default in the desc */
            shade_opts = true;
            break;
        case OPT_ALTITUDE:
            if (!frt_parse_double(optarg, &hd.altitude) || !(hd.altitude > 0.0 && hd.altitude <= 90.0))
                return frt_cli_fail(FRT_EXIT_USAGE, "--altitude must be in (0, 90] degrees, got '%s'", optarg);
            shade_opts = true;
            break;
        case OPT_ZFACTOR:
            if (!parse_auto(optarg, &hd.z_factor) || hd.z_factor < 0.0)
                return frt_cli_fail(FRT_EXIT_USAGE, "--z-factor must be auto or a positive number, got '%s'", optarg);
            shade_opts = true;
            break;
        case OPT_SPACING:
            if (!frt_parse_spacing(optarg, &hd.spacing_x, &hd.spacing_y))
                return frt_cli_fail(FRT_EXIT_USAGE, "--spacing must be D or DX,DY with positive numbers, got '%s'",
                                    optarg);
            have_spacing = shade_opts = true;
            break;
        case OPT_EVERY:
            if (!frt_parse_u32(optarg, &pd.every) || pd.every < 1)
                return frt_cli_fail(FRT_EXIT_USAGE, "--every must be a positive integer, got '%s'", optarg);
            profile_opts = true;
            break;
        case OPT_DILATION:
            if (!parse_auto(optarg, &pd.dilation))
                return frt_cli_fail(FRT_EXIT_USAGE, "--dilation must be auto or a non-zero number, got '%s'", optarg);
            profile_opts = true;
            break;
        case OPT_TILT:
            if (!frt_parse_double(optarg, &pd.tilt) || !(pd.tilt > 0.0 && pd.tilt <= 100.0))
                return frt_cli_fail(FRT_EXIT_USAGE, "--tilt must be a number in (0, 100], got '%s'", optarg);
            profile_opts = true;
            break;
        case OPT_BASE:
            if (!frt_parse_double(optarg, &pd.base) || pd.base < 0.0)
                return frt_cli_fail(FRT_EXIT_USAGE, "--base must be a number >= 0, got '%s'", optarg);
            profile_opts = true;
            break;
        case OPT_WIDTH:
            if (!frt_parse_u32(optarg, &pd.width) || pd.width < 16 || pd.width > 16384)
                return frt_cli_fail(FRT_EXIT_USAGE, "--width must be 16..16384, got '%s'", optarg);
            profile_opts = true;
            break;
        case OPT_LINE_WIDTH:
            if (!frt_parse_double(optarg, &pd.line_width) || !(pd.line_width > 0.0 && pd.line_width <= 100.0))
                return frt_cli_fail(FRT_EXIT_USAGE, "--line-width must be in (0, 100], got '%s'", optarg);
            profile_opts = true;
            break;
        case 'o': output = optarg; break;
        case 'q': quiet = true; break;
        case 'h': render_help(); return FRT_EXIT_OK;
        case ':': return frt_cli_fail(FRT_EXIT_USAGE, "option '%s' needs a value", argv[optind - 1]);
        default: return frt_cli_fail(FRT_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
        }
    }
    if (optind < argc)
        input = argv[optind++];
    if (optind < argc)
        return frt_cli_fail(FRT_EXIT_USAGE, "unexpected argument '%s' (one input; see --help)", argv[optind]);
    if (!input)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing the input heightfield (fracterra render IN -o OUT)");
    if (!output)
        return frt_cli_fail(FRT_EXIT_USAGE, "missing -o OUT (.png; profiles also .svg or .pdf)");
    if (style == STYLE_PROFILES && shade_opts)
        return frt_cli_fail(FRT_EXIT_USAGE, "--azimuth, --altitude, --z-factor and --spacing are for hillshade and "
                                            "color, not profiles");
    if (style != STYLE_PROFILES && profile_opts)
        return frt_cli_fail(FRT_EXIT_USAGE, "--every, --dilation, --tilt, --base, --width and --line-width are for "
                                            "--style profiles");
    const char *dot = strrchr(output, '.');
    bool vector = dot && (strcasecmp(dot, ".svg") == 0 || strcasecmp(dot, ".pdf") == 0);
    if (!(dot && strcasecmp(dot, ".png") == 0) && !(vector && style == STYLE_PROFILES))
        return frt_cli_fail(FRT_EXIT_USAGE, "cannot write '%s': %s renders to .png%s", output,
                            style == STYLE_PROFILES ? "profiles"
                            : style == STYLE_COLOR  ? "color"
                                                    : "hillshade",
                            style == STYLE_PROFILES ? ", .svg or .pdf" : " (SVG and PDF are for --style profiles)");

    char err[1200];
    frt_field_info info;
    frt_result r = frt_read_heightfield_info(input, &info, err, sizeof err);
    if (r != FRT_SUCCESS)
        return frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
    int code = FRT_EXIT_OK;
    if (!frt_cli_probe_writable(output, &code))
        return code;
    size_t count = (size_t)info.width * info.height;
    float *h = malloc(count * sizeof *h);
    uint8_t *pic = NULL;
    if (!h)
        return frt_cli_fail(FRT_EXIT_IO, "cannot allocate %.1f MiB for %u x %u heights",
                            (double)count * 4.0 / 1048576.0, info.width, info.height);
    frt_progress_init(quiet);
    char label[4200];
    snprintf(label, sizeof label, "reading %s", input);
    frt_progress_begin(label, 0);
    r = frt_read_heightfield(input, h, count, &info, err, sizeof err);
    frt_progress_end();
    if (r != FRT_SUCCESS) {
        code = frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
        goto out;
    }
    snprintf(label, sizeof label, "rendering %s", output);
    frt_progress_begin(label, 0);
    if (style == STYLE_PROFILES) {
        r = frt_write_profiles(output, h, info.width, info.height, &pd, err, sizeof err);
    } else {
        hd.color = style == STYLE_COLOR;
        if (!have_spacing) {
            hd.spacing_x = info.spacing_x;
            hd.spacing_y = info.spacing_y;
        }
        size_t bytes = frt_hillshade_size(info.width, info.height, &hd);
        pic = bytes ? malloc(bytes) : NULL;
        r = pic ? frt_hillshade(h, info.width, info.height, &hd, pic, bytes) : FRT_ERROR_OUT_OF_MEMORY;
        if (r == FRT_SUCCESS)
            r = frt_write_picture(output, pic, info.width, info.height, hd.color ? 3 : 1, err, sizeof err);
        else
            snprintf(err, sizeof err, "%s", frt_result_string(r));
    }
    frt_progress_end();
    if (r != FRT_SUCCESS) {
        code = frt_cli_fail(r == FRT_ERROR_IO ? FRT_EXIT_IO : FRT_EXIT_USAGE, "%s", err);
        goto out;
    }
    if (!quiet)
        fprintf(stderr, "%s: %s (%u x %u, %s) -> %s\n", frt_cli_command, input, info.width, info.height,
                style == STYLE_PROFILES ? "profiles"
                : style == STYLE_COLOR  ? "color relief"
                                        : "hillshade",
                output);
out:
    free(pic);
    free(h);
    return code;
}

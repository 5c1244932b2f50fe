/* minimal.c — the smallest use of the library: a 257 x 257 terrain on Vulkan, falling back to the CPU. */
#include <fracterra.h>

#include <stdio.h>
#include <stdlib.h>

int main(void)
{
    frt_terrain_desc desc = {0}; /* zero means default: H 0.8, sigma 1, seed 1 */
    desc.levels = 8;
    size_t count = frt_heightfield_size(&desc);
    float *h = malloc(count * sizeof *h);
    if (!h)
        return 1;
    frt_context *ctx = NULL;
    char err[512];
    frt_result r = frt_context_create(NULL, &ctx, err, sizeof err);
    if (r == FRT_SUCCESS) {
        r = frt_generate(ctx, &desc, h, count, NULL);
        printf("generated on %s: %s\n", frt_context_device(ctx)->name, frt_result_string(r));
        frt_context_destroy(ctx);
    } else {
        fprintf(stderr, "no Vulkan (%s); using the CPU reference\n", err);
        r = frt_generate_cpu(&desc, h, count, NULL);
    }
    if (r == FRT_SUCCESS)
        printf("centre height %.4f\n", h[count / 2]);
    free(h);
    return r == FRT_SUCCESS ? 0 : 1;
}

/* noise_vk.c — runs shaders/noise.comp: Philox words, Gaussians and the distributions of §2.8 on the device for
 * arbitrary counters. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#include "spv_noise.h"

/* Must match `Push` in shaders/noise.comp. */
struct noise_push {
    uint64_t counters, keys, words, gauss;
    uint32_t count;
    uint32_t noise_kind, noise_n; /* 0: raw words and Gaussian; else frt_noise_params kind, n, k, scale */
    float noise_k, noise_scale;
    uint32_t pad;
};
_Static_assert(sizeof(struct noise_push) == 56, "struct noise_push must match Push in shaders/noise.comp");

void frt_noise_vk_release(frt_context *ctx)
{
    if (ctx->noise_pipeline)
        vkDestroyPipeline(ctx->device, ctx->noise_pipeline, NULL);
    if (ctx->noise_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->noise_layout, NULL);
    ctx->noise_pipeline = VK_NULL_HANDLE;
    ctx->noise_layout = VK_NULL_HANDLE;
}

/* `p` NULL: words and the Gaussian of words 0, 1; else the distribution `p` at (i, j, level) = counter words 0..2. */
static frt_result run_noise(frt_context *ctx, const frt_noise_params *p, const uint32_t *counters, const uint32_t *keys,
                            size_t count, uint32_t *words_out, float *gauss_out)
{
    if (!ctx || !counters || !keys || count == 0 || count > (1u << 26))
        return FRT_ERROR_INVALID_ARGUMENT;
    frt_result r = FRT_SUCCESS;
    if (!ctx->noise_pipeline)
        r = frt_pipeline_create(ctx, frt_spv_noise, sizeof frt_spv_noise, sizeof(struct noise_push),
                                &ctx->noise_pipeline, &ctx->noise_layout);
    if (r != FRT_SUCCESS)
        return r;
    /* One host-visible buffer holds the four arrays: counters (16 B), keys (8 B), words (16 B), gauss (4 B). */
    const VkDeviceSize per = 16 + 8 + 16 + 4;
    struct frt_vk_buffer buf;
    r = frt_buffer_create(ctx, per * count, true, &buf);
    if (r != FRT_SUCCESS)
        return r;
    uint8_t *base = buf.mapped;
    memcpy(base, counters, count * 16);
    memcpy(base + count * 16, keys, count * 8);
    struct noise_push pc;
    memset(&pc, 0, sizeof pc);
    pc.counters = buf.address, pc.keys = buf.address + count * 16;
    pc.words = buf.address + count * 24, pc.gauss = buf.address + count * 40;
    pc.count = (uint32_t)count;
    if (p)
        pc.noise_kind = (uint32_t)p->kind, pc.noise_n = p->n, pc.noise_k = p->k, pc.noise_scale = p->scale;
    VkCommandBuffer cmd;
    r = frt_cmd_begin(ctx, &cmd);
    if (r == FRT_SUCCESS) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->noise_pipeline);
        vkCmdPushConstants(cmd, ctx->noise_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        uint32_t groups = (uint32_t)((count + 63) / 64);
        uint32_t gx = groups < 65535 ? groups : 65535, gy = (groups + gx - 1) / gx;
        vkCmdDispatch(cmd, gx, gy, 1);
        VkMemoryBarrier mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, NULL,
                             0, NULL);
        r = frt_cmd_submit_wait(ctx, cmd);
    }
    if (r == FRT_SUCCESS) {
        if (words_out)
            memcpy(words_out, base + count * 24, count * 16);
        if (gauss_out)
            memcpy(gauss_out, base + count * 40, count * 4);
    }
    frt_buffer_destroy(ctx, &buf);
    return r;
}

frt_result frt_noise_vulkan(frt_context *ctx, const uint32_t *counters, const uint32_t *keys, size_t count,
                            uint32_t *words_out, float *gauss_out)
{
    return run_noise(ctx, NULL, counters, keys, count, words_out, gauss_out);
}

frt_result frt_noise_draw_vulkan(frt_context *ctx, const frt_noise_params *p, const uint32_t *points, size_t count,
                                 float *out)
{
    if (!ctx || !p || !points || !out || count == 0 || count > (1u << 26))
        return FRT_ERROR_INVALID_ARGUMENT;
    uint32_t *c = malloc(count * 16), *k = malloc(count * 8);
    frt_result r = c && k ? FRT_SUCCESS : FRT_ERROR_OUT_OF_MEMORY;
    for (size_t n = 0; r == FRT_SUCCESS && n < count; ++n) {
        c[4 * n] = points[3 * n], c[4 * n + 1] = points[3 * n + 1], c[4 * n + 2] = points[3 * n + 2], c[4 * n + 3] = 0;
        k[2 * n] = p->key[0], k[2 * n + 1] = p->key[1];
    }
    if (r == FRT_SUCCESS)
        r = run_noise(ctx, p, c, k, count, NULL, out);
    free(c);
    free(k);
    return r;
}

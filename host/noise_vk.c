/* noise_vk.c — runs shaders/noise.comp: Philox words and Gaussians on the device for arbitrary counters. */
#include "internal.h"

#include <string.h>

#include "spv_noise.h"

struct noise_push {
    uint64_t counters, keys, words, gauss;
    uint32_t count;
    uint32_t pad;
};

void frt_noise_vk_release(frt_context *ctx)
{
    if (ctx->noise_pipeline)
        vkDestroyPipeline(ctx->device, ctx->noise_pipeline, NULL);
    if (ctx->noise_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->noise_layout, NULL);
    ctx->noise_pipeline = VK_NULL_HANDLE;
    ctx->noise_layout = VK_NULL_HANDLE;
}

frt_result frt_noise_vulkan(frt_context *ctx, const uint32_t *counters, const uint32_t *keys, size_t count,
                            uint32_t *words_out, float *gauss_out)
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
    struct noise_push pc = {
        buf.address, buf.address + count * 16, buf.address + count * 24, buf.address + count * 40, (uint32_t)count, 0};
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

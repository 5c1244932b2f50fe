/* generate_vk.c — the Vulkan generator: one compute dispatch per refinement level in one command buffer. */
#include "internal.h"

#include <string.h>

#include "spv_generate_b1.h"
#include "spv_generate_b4.h"
#include "spv_region.h"

/* Must match `Push` in shaders/generate.comp (std430: the uint64 first, then 32-bit words). */
struct generate_push {
    uint64_t grid;
    uint32_t side, level, shift, cells;
    uint32_t key[2];
    float amp_d, amp_s;
    uint32_t mask;  /* coordinates & mask: side - 1 in periodic mode (a torus), else all ones */
    uint32_t lmask; /* lattice coordinates & lmask for the noise: 2^level - 1 in periodic mode, else all ones */
};

/* Must match `Push` in shaders/region.comp (80 bytes, no padding). */
struct region_push {
    uint64_t src, dst;
    int32_t sorg[2], dorg[2];
    uint32_t key[2];
    uint32_t sw, dw, dh, level, last, lmask, periodic;
    float sigma, amp_d, amp_s;
};

enum { LOCAL_SIZE = 8, BLOCK_CELLS = 4 }; /* shaders/generate.comp: local_size 8x8, BLOCK=4 variant */

void frt_generate_vk_release(frt_context *ctx)
{
    for (int i = 0; i < 2; ++i)
        if (ctx->gen_pipeline[i])
            vkDestroyPipeline(ctx->device, ctx->gen_pipeline[i], NULL);
    if (ctx->gen_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->gen_layout, NULL);
    if (ctx->region_pipeline)
        vkDestroyPipeline(ctx->device, ctx->region_pipeline, NULL);
    if (ctx->region_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->region_layout, NULL);
    ctx->gen_pipeline[0] = ctx->gen_pipeline[1] = ctx->region_pipeline = VK_NULL_HANDLE;
    ctx->gen_layout = ctx->region_layout = VK_NULL_HANDLE;
    frt_buffer_destroy(ctx, &ctx->grid);
    frt_buffer_destroy(ctx, &ctx->staging);
}

static frt_result ensure_pipelines(frt_context *ctx)
{
    frt_result r = FRT_SUCCESS;
    if (!ctx->gen_pipeline[0])
        r = frt_pipeline_create(ctx, frt_spv_generate_b1, sizeof frt_spv_generate_b1, sizeof(struct generate_push),
                                &ctx->gen_pipeline[0], &ctx->gen_layout);
    if (r == FRT_SUCCESS && !ctx->gen_pipeline[1])
        r = frt_pipeline_create(ctx, frt_spv_generate_b4, sizeof frt_spv_generate_b4, sizeof(struct generate_push),
                                &ctx->gen_pipeline[1], &ctx->gen_layout);
    if (r == FRT_SUCCESS && !ctx->region_pipeline)
        r = frt_pipeline_create(ctx, frt_spv_region, sizeof frt_spv_region, sizeof(struct region_push),
                                &ctx->region_pipeline, &ctx->region_layout);
    return r;
}

/* The grid buffer is kept between calls and regrown when a larger grid comes. */
static frt_result ensure_buffers(frt_context *ctx, VkDeviceSize bytes)
{
    frt_result r = FRT_SUCCESS;
    if (ctx->grid.buffer && ctx->grid.size < bytes) {
        frt_buffer_destroy(ctx, &ctx->grid);
        frt_buffer_destroy(ctx, &ctx->staging);
    }
    if (!ctx->grid.buffer)
        r = frt_buffer_create(ctx, bytes, false, &ctx->grid);
    /* Device-local memory that is also mappable (lavapipe, integrated GPUs, resizable BAR) is read directly;
     * otherwise the field is copied to a host-visible staging buffer. */
    if (r == FRT_SUCCESS && !ctx->grid.mapped && !ctx->staging.buffer)
        r = frt_buffer_create(ctx, ctx->grid.size, true, &ctx->staging);
    if (r == FRT_ERROR_OUT_OF_MEMORY)
        r = frt_set_error(ctx, FRT_ERROR_TOO_LARGE, "the device could not allocate %.1f MiB for the grid (%s)",
                          (double)bytes / 1048576.0, ctx->error);
    return r;
}

static void barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
                    VkAccessFlags dst_access)
{
    VkMemoryBarrier mb = {VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = src_access;
    mb.dstAccessMask = dst_access;
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &mb, 0, NULL, 0, NULL);
}

/* Ends the command buffer: timestamp, the read-back barrier (and copy of the first `bytes` of the grid buffer to
 * staging when it is not mappable); submits, waits, copies to `out` and fills `info`. */
static frt_result finish(frt_context *ctx, VkCommandBuffer cmd, VkDeviceSize bytes, float *out, uint32_t dispatches,
                         frt_run_info *info, double t0)
{
    if (ctx->timestamps)
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, ctx->timestamps, 1);
    if (ctx->grid.mapped) {
        barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                VK_ACCESS_HOST_READ_BIT);
    } else {
        barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferCopy region = {0, 0, bytes};
        vkCmdCopyBuffer(cmd, ctx->grid.buffer, ctx->staging.buffer, 1, &region);
        barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                VK_ACCESS_HOST_READ_BIT);
    }
    frt_result r = frt_cmd_submit_wait(ctx, cmd);
    if (r != FRT_SUCCESS)
        return r;
    memcpy(out, ctx->grid.mapped ? ctx->grid.mapped : ctx->staging.mapped, (size_t)bytes);

    if (info) {
        memset(info, 0, sizeof *info);
        info->dispatches = dispatches;
        uint64_t ts[2];
        if (ctx->timestamps && vkGetQueryPoolResults(ctx->device, ctx->timestamps, 0, 2, sizeof ts, ts, sizeof ts[0],
                                                     VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
            info->device_seconds = (double)(ts[1] - ts[0]) * (double)ctx->props.limits.timestampPeriod * 1e-9;
        info->total_seconds = frt_now_seconds() - t0;
    }
    return FRT_SUCCESS;
}

/* Regions (§3.2): the grid buffer holds the window (read back) followed by two scratch boxes that the coarser
 * levels alternate between; one dispatch per level, each reading only the previous level's box. */
static frt_result generate_region(frt_context *ctx, const frt_terrain_desc *d, float *out, size_t count,
                                  frt_run_info *info, double t0)
{
    frt_box boxes[FRT_MAX_REGION_LEVELS + 1];
    frt_region_boxes(d, boxes);
    const uint32_t n = d->levels;
    uint64_t scratch = 0;
    for (uint32_t l = 0; l < n; ++l) {
        uint64_t area = (uint64_t)boxes[l].width * boxes[l].height;
        scratch = area > scratch ? area : scratch;
    }
    const uint64_t floats = (uint64_t)count + 2 * scratch;
    const VkDeviceSize bytes = floats * sizeof(float);
    const uint32_t *max_groups = ctx->props.limits.maxComputeWorkGroupCount;
    if (count > UINT32_MAX || scratch > UINT32_MAX || bytes > ctx->info.max_allocation_bytes ||
        bytes > ctx->info.device_local_heap_bytes || (d->region.width + LOCAL_SIZE - 1) / LOCAL_SIZE > max_groups[0] ||
        (d->region.height + LOCAL_SIZE - 1) / LOCAL_SIZE > max_groups[1])
        return frt_set_error(ctx, FRT_ERROR_TOO_LARGE,
                             "a %u x %u region needs %.1f MiB in one allocation and %u x %u workgroups; %s allows "
                             "%.1f MiB per allocation, a %.1f MiB heap and %u x %u workgroups (use a smaller region or "
                             "--backend cpu)",
                             d->region.width, d->region.height, (double)bytes / 1048576.0,
                             (d->region.width + LOCAL_SIZE - 1) / LOCAL_SIZE,
                             (d->region.height + LOCAL_SIZE - 1) / LOCAL_SIZE, ctx->info.name,
                             (double)ctx->info.max_allocation_bytes / 1048576.0,
                             (double)ctx->info.device_local_heap_bytes / 1048576.0, max_groups[0], max_groups[1]);
    frt_result r = ensure_pipelines(ctx);
    if (r == FRT_SUCCESS)
        r = ensure_buffers(ctx, bytes);
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (r == FRT_SUCCESS)
        r = frt_cmd_begin(ctx, &cmd);
    if (r != FRT_SUCCESS)
        return r;
    if (ctx->timestamps) {
        vkCmdResetQueryPool(cmd, ctx->timestamps, 0, 2);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, ctx->timestamps, 0);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->region_pipeline);
    const VkDeviceAddress window = ctx->grid.address,
                          half[2] = {window + count * sizeof(float), window + (count + scratch) * sizeof(float)};
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    struct region_push pc;
    memset(&pc, 0, sizeof pc);
    pc.key[0] = (uint32_t)d->seed;
    pc.key[1] = (uint32_t)(d->seed >> 32);
    pc.periodic = periodic;
    pc.sigma = (float)d->sigma;
    for (uint32_t l = 0; l <= n; ++l) {
        const frt_box db = boxes[l], sb = l ? boxes[l - 1] : boxes[0];
        pc.src = half[(l + 1) & 1];
        pc.dst = l == n ? window : half[l & 1];
        pc.sorg[0] = (int32_t)sb.x, pc.sorg[1] = (int32_t)sb.y;
        pc.dorg[0] = (int32_t)db.x, pc.dorg[1] = (int32_t)db.y;
        pc.sw = sb.width, pc.dw = db.width, pc.dh = db.height;
        pc.level = l;
        pc.last = 1u << l;
        pc.lmask = periodic ? (1u << l) - 1u : UINT32_MAX;
        pc.amp_d = l ? frt_sigma_diamond(d, l) : 0.0f;
        pc.amp_s = l ? frt_sigma_square(d, l) : 0.0f;
        vkCmdPushConstants(cmd, ctx->region_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (db.width + LOCAL_SIZE - 1) / LOCAL_SIZE, (db.height + LOCAL_SIZE - 1) / LOCAL_SIZE, 1);
        if (l < n)
            barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    return finish(ctx, cmd, (VkDeviceSize)count * sizeof(float), out, n + 1, info, t0);
}

frt_result frt_generate(frt_context *ctx, const frt_terrain_desc *desc, float *out, size_t out_count,
                        frt_run_info *info)
{
    if (!ctx)
        return FRT_ERROR_INVALID_ARGUMENT;
    double t0 = frt_now_seconds();
    ctx->error[0] = '\0';
    frt_terrain_desc d;
    if (frt_terrain_desc_resolved(desc, &d) != FRT_SUCCESS)
        return frt_set_error(ctx, FRT_ERROR_INVALID_ARGUMENT, "invalid terrain description");
    size_t count = frt_heightfield_size(&d);
    if (count == 0)
        return frt_set_error(ctx, FRT_ERROR_TOO_LARGE, "grid too large for this host");
    if (!out || out_count < count)
        return frt_set_error(ctx, FRT_ERROR_BUFFER_TOO_SMALL, "output holds %zu floats, the grid needs %zu", out_count,
                             count);
    if (frt_region_is_set(&d.region))
        return generate_region(ctx, &d, out, count, info, t0);
    const VkDeviceSize bytes = (VkDeviceSize)count * sizeof(float);
    if (bytes > ctx->info.max_allocation_bytes || bytes > ctx->info.device_local_heap_bytes)
        return frt_set_error(ctx, FRT_ERROR_TOO_LARGE,
                             "a %u x %u grid needs %.1f MiB in one allocation; %s allows %.1f MiB per allocation "
                             "and has a %.1f MiB heap (use fewer levels or --backend cpu)",
                             frt_terrain_side(&d), frt_terrain_side(&d), (double)bytes / 1048576.0, ctx->info.name,
                             (double)ctx->info.max_allocation_bytes / 1048576.0,
                             (double)ctx->info.device_local_heap_bytes / 1048576.0);
    frt_result r = ensure_pipelines(ctx);
    if (r == FRT_SUCCESS)
        r = ensure_buffers(ctx, bytes);
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (r == FRT_SUCCESS)
        r = frt_cmd_begin(ctx, &cmd);
    if (r != FRT_SUCCESS)
        return r;

    const uint32_t n = d.levels, side = frt_terrain_side(&d);
    const bool periodic = d.edge == FRT_EDGE_PERIODIC;
    if (ctx->timestamps) {
        vkCmdResetQueryPool(cmd, ctx->timestamps, 0, 2);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, ctx->timestamps, 0);
    }
    struct generate_push pc;
    memset(&pc, 0, sizeof pc);
    pc.grid = ctx->grid.address;
    pc.side = side;
    pc.key[0] = (uint32_t)d.seed;
    pc.key[1] = (uint32_t)(d.seed >> 32);
    pc.mask = periodic ? side - 1u : UINT32_MAX;
    int bound = -1;
    for (uint32_t level = 0; level <= n; ++level) {
        pc.level = level;
        pc.shift = n - level;
        pc.cells = level ? 1u << (level - 1) : 1u;
        pc.amp_d = level ? frt_sigma_diamond(&d, level) : (float)d.sigma;
        pc.amp_s = level ? frt_sigma_square(&d, level) : 0.0f;
        pc.lmask = periodic ? (1u << level) - 1u : UINT32_MAX;
        /* Blocks of BLOCK_CELLS^2 cells per invocation once a level has enough cells to fill workgroups. */
        int variant = pc.cells >= LOCAL_SIZE * BLOCK_CELLS ? 1 : 0;
        uint32_t invocations = variant ? pc.cells / BLOCK_CELLS : pc.cells;
        uint32_t groups = (invocations + LOCAL_SIZE - 1) / LOCAL_SIZE;
        if (variant != bound) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->gen_pipeline[variant]);
            bound = variant;
        }
        vkCmdPushConstants(cmd, ctx->gen_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, groups, groups, 1);
        if (level < n)
            barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    return finish(ctx, cmd, bytes, out, n + 1, info, t0);
}

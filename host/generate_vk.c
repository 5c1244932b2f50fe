/* generate_vk.c — the Vulkan generator: one compute dispatch per refinement level in one command buffer. */
#include "internal.h"

#include <stdlib.h>
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
    /* §2.8: frt_noise_params n, k, scale (the kind is the pipeline's specialization) */
    uint32_t noise_n;
    float noise_k, noise_scale;
    uint64_t maps; /* §3.5: address of struct maps_info, or 0 */
};
_Static_assert(sizeof(struct generate_push) == 72, "struct generate_push must match Push in shaders/generate.comp");

/* Must match `Push` in shaders/region.comp (std430: the uint64 at the end starts at 96). */
struct region_push {
    uint64_t src, dst;
    int32_t sorg[2], dorg[2];
    uint32_t key[2];
    uint32_t sw, dw, dh, level, last, lmask, periodic;
    float sigma, amp_d, amp_s;
    /* §2.8: frt_noise_params n, k, scale (the kind is the pipeline's specialization) */
    uint32_t noise_n;
    float noise_k, noise_scale;
    uint32_t pad;
    uint64_t maps; /* §3.5: address of struct maps_info, or 0 */
};
_Static_assert(sizeof(struct region_push) == 104, "struct region_push must match Push in shaders/region.comp");

/* Must match FrtMapInfo in shaders/maps.glsl. */
struct maps_info {
    uint64_t hurst, amplitude; /* addresses of the samples, 0 when absent */
    uint32_t hw, hh, aw, ah;
    float sigma;
    uint32_t pad;
};

enum { LOCAL_SIZE = 8, BLOCK_CELLS = 4 }; /* shaders/generate.comp: local_size 8x8, BLOCK=4 variant */

void frt_generate_vk_release(frt_context *ctx)
{
    for (int slot = 0; slot < FRT_PIPELINE_SLOTS; ++slot) {
        for (int i = 0; i < 2; ++i)
            if (ctx->gen_pipeline[slot][i])
                vkDestroyPipeline(ctx->device, ctx->gen_pipeline[slot][i], NULL);
        if (ctx->region_pipeline[slot])
            vkDestroyPipeline(ctx->device, ctx->region_pipeline[slot], NULL);
    }
    if (ctx->gen_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->gen_layout, NULL);
    if (ctx->region_layout)
        vkDestroyPipelineLayout(ctx->device, ctx->region_layout, NULL);
    memset(ctx->gen_pipeline, 0, sizeof ctx->gen_pipeline);
    memset(ctx->region_pipeline, 0, sizeof ctx->region_pipeline);
    ctx->gen_layout = ctx->region_layout = VK_NULL_HANDLE;
    frt_buffer_destroy(ctx, &ctx->grid);
    frt_buffer_destroy(ctx, &ctx->staging);
    frt_buffer_destroy(ctx, &ctx->maps);
}

/* The pipeline slot for `d`: its noise slot, moved up by FRT_NOISE_SLOTS when it samples maps. */
static uint32_t pipeline_slot(const frt_terrain_desc *d)
{
    const bool maps = d->hurst_map.data || d->amplitude_map.data;
    return frt_noise_slot(d->noise) + (maps ? FRT_NOISE_SLOTS : 0u);
}

/* The pipelines of one slot, made on first use: specialization constant 0 is the noise kind of the slot
 * (FRT_NOISE_KIND in shaders/philox.glsl) and 1 whether it samples maps (FRT_MAPS in shaders/maps.glsl), so that
 * each pipeline carries only its own code. */
static frt_result ensure_pipelines(frt_context *ctx, uint32_t slot)
{
    const uint32_t consts[2] = {slot % FRT_NOISE_SLOTS + 1u, slot / FRT_NOISE_SLOTS};
    const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof consts[0]}, {1, sizeof consts[0], sizeof consts[1]}};
    const VkSpecializationInfo spec = {2, entries, sizeof consts, consts};
    VkPipeline *gen = ctx->gen_pipeline[slot];
    frt_result r = FRT_SUCCESS;
    if (!gen[0])
        r = frt_pipeline_create_spec(ctx, frt_spv_generate_b1, sizeof frt_spv_generate_b1, sizeof(struct generate_push),
                                     &spec, &gen[0], &ctx->gen_layout);
    if (r == FRT_SUCCESS && !gen[1])
        r = frt_pipeline_create_spec(ctx, frt_spv_generate_b4, sizeof frt_spv_generate_b4, sizeof(struct generate_push),
                                     &spec, &gen[1], &ctx->gen_layout);
    if (r == FRT_SUCCESS && !ctx->region_pipeline[slot])
        r = frt_pipeline_create_spec(ctx, frt_spv_region, sizeof frt_spv_region, sizeof(struct region_push), &spec,
                                     &ctx->region_pipeline[slot], &ctx->region_layout);
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

static frt_result generate_grid(frt_context *ctx, const frt_terrain_desc *d, const float *completed, float *out,
                                size_t count, frt_run_info *info, double t0);

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

static int64_t floor_half(int64_t a)
{
    return a >= 0 ? a / 2 : -((1 - a) / 2);
}

/* Maps (§3.5): the info block and the samples in one host-visible buffer (kept, regrown); *address is 0 without
 * maps. The shaders read them through buffer device addresses. */
static frt_result upload_maps(frt_context *ctx, const frt_terrain_desc *d, VkDeviceAddress *address)
{
    *address = 0;
    if (!d->hurst_map.data && !d->amplitude_map.data)
        return FRT_SUCCESS;
    const VkDeviceSize hbytes = d->hurst_map.data ? (VkDeviceSize)d->hurst_map.width * d->hurst_map.height * 4 : 0;
    const VkDeviceSize abytes =
        d->amplitude_map.data ? (VkDeviceSize)d->amplitude_map.width * d->amplitude_map.height * 4 : 0;
    const VkDeviceSize hat = sizeof(struct maps_info), aat = (hat + hbytes + 7) & ~(VkDeviceSize)7;
    const VkDeviceSize bytes = aat + abytes;
    if (ctx->maps.buffer && ctx->maps.size < bytes)
        frt_buffer_destroy(ctx, &ctx->maps);
    if (!ctx->maps.buffer) {
        frt_result r = frt_buffer_create(ctx, bytes, true, &ctx->maps);
        if (r != FRT_SUCCESS)
            return r;
    }
    struct maps_info info = {0};
    char *base = ctx->maps.mapped;
    if (hbytes) {
        memcpy(base + hat, d->hurst_map.data, (size_t)hbytes);
        info.hurst = ctx->maps.address + hat;
        info.hw = d->hurst_map.width, info.hh = d->hurst_map.height;
    }
    if (abytes) {
        memcpy(base + aat, d->amplitude_map.data, (size_t)abytes);
        info.amplitude = ctx->maps.address + aat;
        info.aw = d->amplitude_map.width, info.ah = d->amplitude_map.height;
    }
    info.sigma = (float)d->sigma;
    memcpy(base, &info, sizeof info);
    *address = ctx->maps.address;
    return FRT_SUCCESS;
}

/* Densify (§3.4): puts `floats` heights at float offset `at` of the grid buffer before the first dispatch — straight
 * into mapped memory (made visible by the submit), or through the staging buffer and a recorded copy. */
static void upload(frt_context *ctx, VkCommandBuffer cmd, const float *src, VkDeviceSize at, VkDeviceSize floats)
{
    const VkDeviceSize off = at * sizeof(float), bytes = floats * sizeof(float);
    if (ctx->grid.mapped) {
        memcpy((char *)ctx->grid.mapped + off, src, (size_t)bytes);
        return;
    }
    memcpy((char *)ctx->staging.mapped + off, src, (size_t)bytes);
    VkBufferCopy region = {off, off, bytes};
    vkCmdCopyBuffer(cmd, ctx->staging.buffer, ctx->grid.buffer, 1, &region);
    barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

/* Regions (§3.2): the grid buffer holds the window (read back) followed by two scratch boxes that the coarser
 * levels alternate between; one dispatch per level, each reading only the previous level's box. */
static frt_result generate_region(frt_context *ctx, const frt_terrain_desc *d, const float *completed, float *out,
                                  size_t count, frt_run_info *info, double t0)
{
    frt_box boxes[FRT_MAX_REGION_LEVELS + 1];
    const uint64_t scratch = frt_region_boxes(d, boxes);
    const uint32_t n = d->levels;
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
    const uint32_t slot = pipeline_slot(d);
    frt_result r = ensure_pipelines(ctx, slot);
    if (r == FRT_SUCCESS)
        r = ensure_buffers(ctx, bytes);
    VkDeviceAddress maps = 0;
    if (r == FRT_SUCCESS)
        r = upload_maps(ctx, d, &maps);
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    if (r == FRT_SUCCESS)
        r = frt_cmd_begin(ctx, &cmd);
    if (r != FRT_SUCCESS)
        return r;
    if (ctx->timestamps) {
        vkCmdResetQueryPool(cmd, ctx->timestamps, 0, 2);
        vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, ctx->timestamps, 0);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->region_pipeline[slot]);
    const VkDeviceAddress window = ctx->grid.address,
                          half[2] = {window + count * sizeof(float), window + (count + scratch) * sizeof(float)};
    const bool periodic = d->edge == FRT_EDGE_PERIODIC;
    struct region_push pc;
    memset(&pc, 0, sizeof pc);
    pc.maps = maps;
    pc.key[0] = (uint32_t)d->seed;
    pc.key[1] = (uint32_t)(d->seed >> 32);
    frt_noise_params np;
    frt_noise_params_init(&np, d);
    pc.noise_n = np.n, pc.noise_k = np.k, pc.noise_scale = np.scale;
    pc.periodic = periodic;
    pc.sigma = (float)d->sigma;
    uint32_t first = 0;
    if (completed) { /* level k's box comes from the completed coarse grid; levels k+1..n are dispatched */
        first = d->coarse_levels + 1;
        const frt_box kb = boxes[d->coarse_levels];
        const size_t area = (size_t)kb.width * kb.height;
        float *box = malloc(area * sizeof *box);
        if (!box) {
            vkFreeCommandBuffers(ctx->device, ctx->pool, 1, &cmd);
            return frt_set_error(ctx, FRT_ERROR_OUT_OF_MEMORY, "no memory for the coarse box");
        }
        frt_coarse_box(d, completed, &kb, box);
        upload(ctx, cmd, box, first - 1 == n ? 0 : count + (uint64_t)((first - 1) & 1) * scratch, area);
        free(box);
    }
    for (uint32_t l = first; l <= n; ++l) {
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
        /* one invocation per 2 x 2 quad whose corner has even coordinates (shaders/region.comp) */
        const uint32_t qw = (uint32_t)(floor_half(db.x + db.width - 1) - floor_half(db.x) + 1);
        const uint32_t qh = (uint32_t)(floor_half(db.y + db.height - 1) - floor_half(db.y) + 1);
        vkCmdDispatch(cmd, (qw + LOCAL_SIZE - 1) / LOCAL_SIZE, (qh + LOCAL_SIZE - 1) / LOCAL_SIZE, 1);
        if (l < n)
            barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    return finish(ctx, cmd, (VkDeviceSize)count * sizeof(float), out, n + 1 - first, info, t0);
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
    float *completed = NULL;
    if (d.coarse) {
        frt_result r = frt_coarse_complete(&d, &completed);
        if (r != FRT_SUCCESS)
            return frt_set_error(ctx, r, "no memory to complete the coarse grid");
    }
    frt_result r = frt_region_is_set(&d.region) ? generate_region(ctx, &d, completed, out, count, info, t0)
                                                : generate_grid(ctx, &d, completed, out, count, info, t0);
    free(completed);
    return r;
}

/* The whole grid: one dispatch per level (levels k+1..n when densifying). */
static frt_result generate_grid(frt_context *ctx, const frt_terrain_desc *dp, const float *completed, float *out,
                                size_t count, frt_run_info *info, double t0)
{
    const frt_terrain_desc d = *dp;
    const VkDeviceSize bytes = (VkDeviceSize)count * sizeof(float);
    if (bytes > ctx->info.max_allocation_bytes || bytes > ctx->info.device_local_heap_bytes)
        return frt_set_error(ctx, FRT_ERROR_TOO_LARGE,
                             "a %u x %u grid needs %.1f MiB in one allocation; %s allows %.1f MiB per allocation "
                             "and has a %.1f MiB heap (use fewer levels or --backend cpu)",
                             frt_terrain_side(&d), frt_terrain_side(&d), (double)bytes / 1048576.0, ctx->info.name,
                             (double)ctx->info.max_allocation_bytes / 1048576.0,
                             (double)ctx->info.device_local_heap_bytes / 1048576.0);
    const uint32_t slot = pipeline_slot(&d);
    frt_result r = ensure_pipelines(ctx, slot);
    if (r == FRT_SUCCESS)
        r = ensure_buffers(ctx, bytes);
    VkDeviceAddress maps = 0;
    if (r == FRT_SUCCESS)
        r = upload_maps(ctx, &d, &maps);
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
    pc.maps = maps;
    pc.grid = ctx->grid.address;
    pc.side = side;
    pc.key[0] = (uint32_t)d.seed;
    pc.key[1] = (uint32_t)(d.seed >> 32);
    frt_noise_params np;
    frt_noise_params_init(&np, &d);
    pc.noise_n = np.n, pc.noise_k = np.k, pc.noise_scale = np.scale;
    pc.mask = periodic ? side - 1u : UINT32_MAX;
    int bound = -1;
    uint32_t first = 0;
    if (completed) { /* the completed coarse grid at spacing 2^(n-k), row by row */
        const uint32_t k = d.coarse_levels, step = 1u << (n - k), cs = frt_grid_side(k) - (periodic ? 1u : 0u);
        first = k + 1;
        float *row = malloc((size_t)side * sizeof *row);
        if (!row) {
            vkFreeCommandBuffers(ctx->device, ctx->pool, 1, &cmd);
            return frt_set_error(ctx, FRT_ERROR_OUT_OF_MEMORY, "no memory for a row");
        }
        for (uint32_t y = 0; y < cs; ++y) {
            /* whole rows, so that one copy per row suffices: the points between are overwritten by later levels */
            for (uint32_t x = 0; x < side; ++x)
                row[x] = (x % step == 0) ? completed[(size_t)y * cs + x / step] : 0.0f;
            upload(ctx, cmd, row, (VkDeviceSize)(y * step) * side, side);
        }
        free(row);
    }
    for (uint32_t level = first; level <= n; ++level) {
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
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, ctx->gen_pipeline[slot][variant]);
            bound = variant;
        }
        vkCmdPushConstants(cmd, ctx->gen_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, groups, groups, 1);
        if (level < n)
            barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                    VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    return finish(ctx, cmd, bytes, out, n + 1 - first, info, t0);
}

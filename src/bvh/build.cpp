#include "bvh/build.h"

#include <algorithm>
#include <atomic>
#include <future>
#include <thread>

#include "util/error.h"
#include "util/timer.h"

namespace wp::bvh {

namespace {

struct Builder {
    std::span<const Aabb> boxes;
    std::vector<glm::vec3> centroids;
    std::vector<std::uint32_t>& order;
    std::vector<Node>& nodes;
    std::atomic<int> node_count{0};
    std::atomic<int> max_depth_seen{0};
    BuildOptions opt;
    int parallel_depth = 0;     // subtrees forked in parallel down to this depth
    static constexpr int kParallelMin = 4096;

    int alloc_node() { return node_count.fetch_add(1); }

    // Builds the subtree over order[first, first + count) into node `index`.
    void build_node(int index, int first, int count, int depth) {
        Node& node = nodes[index];
        Aabb box, cbox;
        for (int i = first; i < first + count; ++i) {
            box.grow(boxes[order[i]]);
            cbox.grow(centroids[order[i]]);
        }
        node.box = box;

        int mid = -1;
        if (count > 1 && depth < opt.max_depth) {
            bool median = depth >= opt.max_depth - 24;
            if (!median) mid = sah_split(first, count, box, cbox, depth);
            if (mid == -2) mid = -1;  // the SAH prefers a leaf
            else if (mid < 0 && count > opt.max_leaf) median = true;
            if (median) mid = median_split(first, count, cbox);
        }
        if (mid < 0) {
            if (count > opt.max_leaf)
                fail("BVH build: {} primitives left at depth {} (cap {}); cannot form a leaf", count, depth,
                     opt.max_depth);
            node.first = first;
            node.count = count;
            int d = depth - 1;  // interior levels above this leaf
            int seen = max_depth_seen.load();
            while (d > seen && !max_depth_seen.compare_exchange_weak(seen, d)) {
            }
            return;
        }
        int left = alloc_node(), right = alloc_node();
        node.left = left;
        node.right = right;
        int nl = mid - first, nr = count - nl;
        if (depth <= parallel_depth && nl > kParallelMin && nr > kParallelMin) {
            auto f = std::async(std::launch::async, [&, left, first, nl, depth] { build_node(left, first, nl, depth + 1); });
            build_node(right, mid, nr, depth + 1);
            f.get();
        } else {
            build_node(left, first, nl, depth + 1);
            build_node(right, mid, nr, depth + 1);
        }
    }

    // Object median along the widest centroid axis (index order when all centroids agree).
    int median_split(int first, int count, const Aabb& cbox) {
        glm::vec3 e = cbox.extent();
        int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
        int mid = first + count / 2;
        if (e[axis] > 0.0f) {
            std::nth_element(order.begin() + first, order.begin() + mid, order.begin() + first + count,
                             [&](std::uint32_t a, std::uint32_t b) {
                                 float ca = centroids[a][axis], cb = centroids[b][axis];
                                 return ca < cb || (ca == cb && a < b);
                             });
        }
        return mid;
    }

    // Binned SAH. Returns the partition point, -2 when a leaf is cheaper, -1 when no
    // split separates the centroids.
    int sah_split(int first, int count, const Aabb& box, const Aabb& cbox, int) {
        const int nb = opt.bins;
        glm::vec3 ext = cbox.extent();
        float best_cost = std::numeric_limits<float>::max();
        int best_axis = -1, best_bin = -1;
        std::vector<Aabb> bin_box(nb);
        std::vector<int> bin_count(nb);
        std::vector<float> right_area(nb);
        std::vector<int> right_count(nb);
        for (int axis = 0; axis < 3; ++axis) {
            if (!(ext[axis] > 0.0f)) continue;
            float scale = nb / ext[axis];
            std::fill(bin_box.begin(), bin_box.end(), Aabb{});
            std::fill(bin_count.begin(), bin_count.end(), 0);
            for (int i = first; i < first + count; ++i) {
                std::uint32_t p = order[i];
                int b = std::min(nb - 1, static_cast<int>((centroids[p][axis] - cbox.lo[axis]) * scale));
                bin_box[b].grow(boxes[p]);
                bin_count[b] += 1;
            }
            // Sweep from the right, then from the left evaluating each plane.
            Aabb acc;
            int n = 0;
            for (int b = nb - 1; b > 0; --b) {
                acc.grow(bin_box[b]);
                n += bin_count[b];
                right_area[b] = acc.half_area();
                right_count[b] = n;
            }
            acc = Aabb{};
            n = 0;
            for (int b = 0; b < nb - 1; ++b) {
                acc.grow(bin_box[b]);
                n += bin_count[b];
                int nr = right_count[b + 1];
                if (n == 0 || nr == 0) continue;
                float cost = acc.half_area() * n + right_area[b + 1] * nr;
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_bin = b;
                }
            }
        }
        if (best_axis < 0) return -1;
        float parent_area = box.half_area();
        float split_cost = opt.traversal_cost + (parent_area > 0.0f ? best_cost / parent_area : count);
        if (count <= opt.max_leaf && split_cost >= static_cast<float>(count)) return -2;
        float scale = nb / ext[best_axis];
        float lo = cbox.lo[best_axis];
        auto it = std::partition(order.begin() + first, order.begin() + first + count, [&](std::uint32_t p) {
            int b = std::min(nb - 1, static_cast<int>((centroids[p][best_axis] - lo) * scale));
            return b <= best_bin;
        });
        int mid = static_cast<int>(it - order.begin());
        if (mid == first || mid == first + count) return -1;
        return mid;
    }
};

}  // namespace

Bvh build(std::span<const Aabb> prim_boxes, const BuildOptions& options) {
    Timer timer;
    Bvh bvh;
    int n = static_cast<int>(prim_boxes.size());
    if (options.max_leaf < 1 || options.max_leaf > 31) fail("BVH build: max_leaf must be in 1..31");
    bvh.prim_order.resize(n);
    for (int i = 0; i < n; ++i) bvh.prim_order[i] = static_cast<std::uint32_t>(i);
    if (n == 0) {
        bvh.build_ms = timer.ms();
        return bvh;
    }
    bvh.nodes.resize(2 * static_cast<std::size_t>(n));
    Builder b{prim_boxes, {}, bvh.prim_order, bvh.nodes, {}, {}, options, 0};
    b.opt = options;
    int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
    while ((1 << b.parallel_depth) < threads) ++b.parallel_depth;
    b.parallel_depth += 2;  // a little more parallelism than threads, for load balance
    if (threads <= 1) b.parallel_depth = 0;
    b.centroids.resize(n);
    for (int i = 0; i < n; ++i) b.centroids[i] = prim_boxes[i].center();
    b.node_count = 1;
    b.build_node(0, 0, n, 1);
    bvh.nodes.resize(b.node_count.load());
    bvh.depth = b.max_depth_seen.load();
    bvh.build_ms = timer.ms();
    return bvh;
}

double sah_cost(const Bvh& bvh, float traversal_cost) {
    if (bvh.nodes.empty()) return 0.0;
    double root = bvh.nodes[0].box.half_area();
    if (root <= 0.0) return 0.0;
    double cost = 0.0;
    for (const auto& nd : bvh.nodes) {
        double a = nd.box.half_area() / root;
        cost += nd.leaf() ? a * nd.count : a * traversal_cost;
    }
    return cost;
}

}  // namespace wp::bvh

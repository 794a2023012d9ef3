#include "optim/network/camera_block.hpp"

#include <algorithm>

namespace rangecal {
namespace {

/// The four blocks in canonical order and back (reprojection_cost.hpp's block layout).
void blocks_to_canonical(const BundleParameterBlocks& b, double* out) {
  out = std::copy(b.intr, b.intr + kIntrinsicsBlockSize, out);
  out = std::copy(b.dist, b.dist + kDistortionBlockSize, out);
  out = std::copy(b.pose, b.pose + kPoseBlockSize, out);
  std::copy(b.clock, b.clock + kClockBlockSize, out);
}

void canonical_to_blocks(const double* in, BundleParameterBlocks* b) {
  std::copy(in, in + kIntrinsicsBlockSize, b->intr);
  in += kIntrinsicsBlockSize;
  std::copy(in, in + kDistortionBlockSize, b->dist);
  in += kDistortionBlockSize;
  std::copy(in, in + kPoseBlockSize, b->pose);
  in += kPoseBlockSize;
  std::copy(in, in + kClockBlockSize, b->clock);
}

}  // namespace

CameraBlock CameraBlock::pack(const BundleSetup& setup, const BundleParameterBlocks& blocks,
                              const Camera& base) {
  CameraBlock c;
  blocks_to_canonical(blocks, c.all.data());
  for (int i = 0; i < kBundleParameterCount; ++i)
    if (setup.free[static_cast<std::size_t>(i)]) {
      c.index[static_cast<std::size_t>(c.size)] = i;
      c.values[static_cast<std::size_t>(c.size)] = c.all[static_cast<std::size_t>(i)];
      ++c.size;
    }
  c.R0 = blocks.R0;
  c.dx_mm = base.intr.dx_mm, c.dy_mm = base.intr.dy_mm;
  return c;
}

void CameraBlock::expand(const double* x, double* out) const {
  std::copy(all.begin(), all.end(), out);
  const double* v = x ? x : values.data();
  for (int j = 0; j < size; ++j) out[index[static_cast<std::size_t>(j)]] = v[j];
}

void CameraBlock::prepare_evaluation() {
  for (int j = 0; j < size; ++j)
    all[index[static_cast<std::size_t>(j)]] = values[static_cast<std::size_t>(j)];
  rotation = pose_rotation(all.data() + kIntrinsicsBlockSize + kDistortionBlockSize, R0);
}

void CameraBlock::unpack(BundleParameterBlocks* blocks) const {
  double a[kBundleParameterCount];
  expand(nullptr, a);
  canonical_to_blocks(a, blocks);
}

}  // namespace rangecal

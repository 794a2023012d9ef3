#pragma once
// Points' camera columns gathered a chunk at a time: the three columns of each of up to
// kPointChunk points side by side in one matrix H with a row per camera parameter (zero where a
// camera did not see the point), so that one matrix product serves the whole chunk — S −= H·Hᵀ,
// one rank-3m update of the reduced camera system, or Σ_cc·H for the points' covariances — in
// place of one small product per point (docs/performance.md).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace rangecal {

/// Points per chunk.
inline constexpr int kPointChunk = 256;

class PointChunk {
 public:
  /// A chunk `rows` high in `storage`, set to zero: a caller that forms many keeps one allocation.
  PointChunk(Eigen::Index rows, Eigen::MatrixXd* storage) : H_(storage) {
    H_->setZero(rows, 3 * kPointChunk);
  }
  PointChunk(const PointChunk&) = delete;
  PointChunk& operator=(const PointChunk&) = delete;

  /// Takes point k into the chunk; returns the first of its three columns of matrix(), which are
  /// zero.
  Eigen::Index add(std::size_t k) {
    const Eigen::Index at = columns();
    points_.push_back(k);
    return at;
  }
  bool full() const { return points_.size() == static_cast<std::size_t>(kPointChunk); }
  bool empty() const { return points_.empty(); }
  /// The chunk's points in the order taken; the i-th has columns 3i to 3i + 2.
  const std::vector<std::size_t>& points() const { return points_; }
  /// H, every column: the chunk's points fill the first columns().
  Eigen::MatrixXd& matrix() { return *H_; }
  Eigen::Index columns() const { return 3 * static_cast<Eigen::Index>(points_.size()); }
  /// The filled columns of H.
  auto filled() { return H_->leftCols(columns()); }
  /// Zeroes the filled columns and empties the chunk.
  void clear() {
    filled().setZero();
    points_.clear();
  }

 private:
  Eigen::MatrixXd* H_;
  std::vector<std::size_t> points_;
};

/// S −= H·Hᵀ over the chunk's filled columns, on S's lower triangle only (the upper is left as it
/// was); the chunk is then emptied. Nothing for an empty chunk.
inline void subtract_chunk_outer_product(PointChunk* chunk, Eigen::MatrixXd* S) {
  if (chunk->empty()) return;
  S->selfadjointView<Eigen::Lower>().rankUpdate(chunk->filled(), -1.0);
  chunk->clear();
}

}  // namespace rangecal

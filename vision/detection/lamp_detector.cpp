#include "vision/detection/lamp_detector.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <ceres/tiny_solver.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <exception>
#include <unordered_map>

#include "config/error.hpp"
#include "vision/frames/frame_source.hpp"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rangecal {

namespace {

constexpr int kBlock = 16;         // coarse block size (px)
constexpr int kNoiseRowStep = 32;  // 25 rows of 1280 px: σ to ≈ 0.5 %
constexpr int kGrowRadius = 40;    // region growing stays within ±40 px of its seed
constexpr int kGrowSide = 2 * kGrowRadius + 1;

// Per-thread scratch, reused across frames so the search allocates nothing in steady state.
struct Workspace {
  std::vector<std::uint32_t> hist;
  std::vector<std::uint16_t> bmax;
  std::vector<std::uint64_t> bsum;
  std::vector<std::uint32_t> bcount;
  std::vector<float> bmean;
  std::vector<std::uint8_t> mask = std::vector<std::uint8_t>(kGrowSide * kGrowSide, 0);
  std::vector<int> stack;
  std::vector<int> visited;
};

Workspace& workspace() {
  thread_local Workspace ws;
  return ws;
}

// ---- 1. noise: σ = 1.4826·median|I(x+1) − I(x)| / √2 on every 32nd row ------------------------
template <typename T>
double estimate_noise(const cv::Mat& img, Workspace& ws) {
  constexpr int kBins = 1024;
  ws.hist.assign(kBins, 0);
  std::uint64_t n = 0;
  for (int y = kNoiseRowStep / 2; y < img.rows; y += kNoiseRowStep) {
    const T* p = img.ptr<T>(y);
    for (int x = 0; x + 1 < img.cols; ++x) {
      const int d = std::abs(static_cast<int>(p[x + 1]) - static_cast<int>(p[x]));
      ++ws.hist[static_cast<std::size_t>(std::min(d, kBins - 1))];
    }
    n += static_cast<std::uint64_t>(img.cols - 1);
  }
  if (n == 0) return 1.0;
  // Median of the integer-valued |d|, interpolated inside its bin (bin k spans [k − ½, k + ½)).
  const double half = 0.5 * static_cast<double>(n);
  double cum = 0;
  double med = 0;
  for (int k = 0; k < kBins; ++k) {
    const double h = ws.hist[static_cast<std::size_t>(k)];
    if (cum + h >= half) {
      const double lo = k == 0 ? 0.0 : k - 0.5;
      const double width = k == 0 ? 0.5 : 1.0;
      med = lo + width * (half - cum) / std::max(h, 1.0);
      break;
    }
    cum += h;
  }
  return std::max(1.4826 * med / std::sqrt(2.0), 0.5);  // ≥ 0.5 DN: quantisation floor
}

// ---- 2. 16×16 block max and sum ---------------------------------------------------------------
template <typename T>
void block_stats_scalar(const cv::Mat& img, int nbx, int nby, Workspace& ws) {
  for (int by = 0; by < nby; ++by) {
    const int y0 = by * kBlock, y1 = std::min(img.rows, y0 + kBlock);
    for (int y = y0; y < y1; ++y) {
      const T* p = img.ptr<T>(y);
      for (int bx = 0; bx < nbx; ++bx) {
        const int x0 = bx * kBlock, x1 = std::min(img.cols, x0 + kBlock);
        unsigned m = 0;
        std::uint32_t s = 0;
        for (int x = x0; x < x1; ++x) {
          m = std::max<unsigned>(m, p[x]);
          s += p[x];
        }
        const std::size_t b = static_cast<std::size_t>(by) * nbx + bx;
        ws.bmax[b] = static_cast<std::uint16_t>(std::max<unsigned>(ws.bmax[b], m));
        ws.bsum[b] += s;
      }
    }
  }
}

#if defined(__SSE2__)
// 8-bit fast path: per block, 16 loads, max and SAD accumulated in registers (the 16 rows of a
// block row, 20 KB at 1280 px, stay in L1 while the block columns are swept).
void block_stats_u8_sse2(const cv::Mat& img, int nbx, int nby, Workspace& ws) {
  const int full = img.cols / kBlock;  // blocks fully 16 wide
  const __m128i zero = _mm_setzero_si128();
  const std::uint8_t* rows[kBlock];
  for (int by = 0; by < nby; ++by) {
    const int y0 = by * kBlock, y1 = std::min(img.rows, y0 + kBlock);
    const int nr = y1 - y0;
    for (int r = 0; r < nr; ++r) rows[r] = img.ptr<std::uint8_t>(y0 + r);
    for (int bx = 0; bx < full; ++bx) {
      __m128i m0 = zero, m1 = zero, s0 = zero, s1 = zero;
      int r = 0;
      for (; r + 2 <= nr; r += 2) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rows[r] + bx * kBlock));
        const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rows[r + 1] + bx * kBlock));
        m0 = _mm_max_epu8(m0, a);
        m1 = _mm_max_epu8(m1, b);
        s0 = _mm_add_epi64(s0, _mm_sad_epu8(a, zero));
        s1 = _mm_add_epi64(s1, _mm_sad_epu8(b, zero));
      }
      if (r < nr) {
        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(rows[r] + bx * kBlock));
        m0 = _mm_max_epu8(m0, a);
        s0 = _mm_add_epi64(s0, _mm_sad_epu8(a, zero));
      }
      __m128i m = _mm_max_epu8(m0, m1);
      m = _mm_max_epu8(m, _mm_srli_si128(m, 8));
      m = _mm_max_epu8(m, _mm_srli_si128(m, 4));
      m = _mm_max_epu8(m, _mm_srli_si128(m, 2));
      m = _mm_max_epu8(m, _mm_srli_si128(m, 1));
      const __m128i s = _mm_add_epi64(s0, s1);
      const std::size_t b = static_cast<std::size_t>(by) * nbx + bx;
      ws.bmax[b] = static_cast<std::uint16_t>(_mm_cvtsi128_si32(m) & 0xFF);
      ws.bsum[b] = static_cast<std::uint64_t>(_mm_cvtsi128_si32(s)) +
                   static_cast<std::uint64_t>(_mm_cvtsi128_si32(_mm_srli_si128(s, 8)));
    }
    if (full < nbx) {  // the last, partial block column
      const int bx = nbx - 1;
      const std::size_t b = static_cast<std::size_t>(by) * nbx + bx;
      for (int r = 0; r < nr; ++r)
        for (int x = bx * kBlock; x < img.cols; ++x) {
          ws.bmax[b] = std::max<std::uint16_t>(ws.bmax[b], rows[r][x]);
          ws.bsum[b] += rows[r][x];
        }
    }
  }
}
#endif

// ---- 6. pixel-integrated Gaussian fit --------------------------------------------------------
struct FitResult {
  bool ok = false;
  double u = 0, v = 0, sigma = 0, flux = 0, background = 0;
};

constexpr int kFitMax = 64;  // the fit window is at most kFitMax − 1 px on a side
using FitParams = Eigen::Matrix<double, 5, 1>;

// The pixels of the fit window [x0, x0 + nx − 1] × [y0, y0 + ny − 1], row-major; use = below
// saturation.
struct FitWindow {
  int x0 = 0, y0 = 0, nx = 0, ny = 0;
  double data[kFitMax * kFitMax];
  bool use[kFitMax * kFitMax];
};

// Reads the window; returns the number of unsaturated pixels and *sum_above = Σ (value − b_init).
template <typename T>
int read_fit_window(const cv::Mat& img, int sat, double b_init, FitWindow& w, double* sum_above) {
  int n_used = 0;
  *sum_above = 0;
  for (int j = 0; j < w.ny; ++j) {
    const T* p = img.ptr<T>(w.y0 + j);
    for (int i = 0; i < w.nx; ++i) {
      const int val = p[w.x0 + i];
      w.data[j * w.nx + i] = val;
      w.use[j * w.nx + i] = val < sat;
      n_used += w.use[j * w.nx + i];
      *sum_above += val - b_init;
    }
  }
  return n_used;
}

// The PSF of width s about centre c integrated over pixels o … o + n − 1 (frame_renderer.hpp):
// e[i] = Φ(right edge) − Φ(left edge), with its derivatives by the centre (de) and by σ (ds).
void pixel_integrals(int n, int o, double c, double s, double* e, double* de, double* ds) {
  static const double kInvSqrt2Pi = 0.3989422804014327;
  const double k = 1.0 / (std::sqrt(2.0) * s);
  double Phi_prev = 0, phi_prev = 0, t_prev = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = (o + i - 0.5) - c;
    const double Phi = 0.5 * std::erf(t * k);
    const double phi = kInvSqrt2Pi / s * std::exp(-0.5 * t * t / (s * s));
    if (i > 0) {
      e[i - 1] = Phi - Phi_prev;
      de[i - 1] = -(phi - phi_prev);                   // ∂E/∂centre
      ds[i - 1] = -(t * phi - t_prev * phi_prev) / s;  // ∂E/∂σ
    }
    Phi_prev = Phi;
    phi_prev = phi;
    t_prev = t;
  }
}

// Residuals m − data of m(x, y) = b + F·Ex(x)·Ey(y) over the window's used pixels at
// q = (F, u, v, σ, b), and their Jacobian, for ceres::TinySolver. Outside σ ∈ (0.2, 20) px or
// F > 0 the residuals are huge, so the solver rejects the step (TinySolver has no bounds).
struct GaussianWindowResiduals {
  using Scalar = double;
  enum { NUM_RESIDUALS = Eigen::Dynamic, NUM_PARAMETERS = 5 };
  const FitWindow& w;
  int n_used;

  int NumResiduals() const { return n_used; }
  bool operator()(const double* q, double* res, double* jac) const {
    if (!(q[3] > 0.2 && q[3] < 20 && q[0] > 0)) {
      std::fill(res, res + n_used, 1e100);
      return true;
    }
    double ex[kFitMax], dxu[kFitMax], dxs[kFitMax], ey[kFitMax], dyv[kFitMax], dys[kFitMax];
    pixel_integrals(w.nx, w.x0, q[1], q[3], ex, dxu, dxs);
    pixel_integrals(w.ny, w.y0, q[2], q[3], ey, dyv, dys);
    const double F = q[0], b = q[4];
    int k = 0;
    for (int j = 0; j < w.ny; ++j)
      for (int i = 0; i < w.nx; ++i) {
        if (!w.use[j * w.nx + i]) continue;
        res[k] = b + F * ex[i] * ey[j] - w.data[j * w.nx + i];
        if (jac) {  // column-major n_used × 5
          jac[k] = ex[i] * ey[j];
          jac[n_used + k] = F * dxu[i] * ey[j];
          jac[2 * n_used + k] = F * ex[i] * dyv[j];
          jac[3 * n_used + k] = F * (dxs[i] * ey[j] + ex[i] * dys[j]);
          jac[4 * n_used + k] = 1.0;
        }
        ++k;
      }
    return true;
  }
};

// Least squares of m(x, y) = b + F·Ex(x)·Ey(y) over the window [x0, x1] × [y0, y1], pixels ≥ sat
// excluded. Ex is the PSF integrated over the pixel (see frame_renderer.hpp), so the model matches
// how a sensor samples a blurred point: no sampling bias. Parameters p = (F, u, v, σ, b).
template <typename T>
FitResult fit_gaussian(const cv::Mat& img, int x0, int x1, int y0, int y1, int sat, double u_init,
                       double v_init, double s_init, double b_init) {
  FitWindow w;
  w.x0 = x0;
  w.y0 = y0;
  w.nx = x1 - x0 + 1;
  w.ny = y1 - y0 + 1;
  if (w.nx > kFitMax - 1 || w.ny > kFitMax - 1 || w.nx < 3 || w.ny < 3) return {};
  double sum_above = 0;
  const int n_used = read_fit_window<T>(img, sat, b_init, w, &sum_above);
  if (n_used < 8) return {};
  FitParams p;
  p << std::max(sum_above, 1.0), u_init, v_init, s_init, b_init;
  // ceres::TinySolver's Levenberg–Marquardt. It stops when the step is below 1e-9 of ‖p‖ (≈ 1e-6 px
  // for a lamp of flux ~1000 DN, far below the 0.02 px bias budget) or the cost stops changing.
  using Solver = ceres::TinySolver<GaussianWindowResiduals>;
  Solver solver;
  solver.options.max_num_iterations = 30;
  solver.options.parameter_tolerance = 1e-9;
  solver.options.function_tolerance = 1e-9;
  solver.options.gradient_tolerance = 1e-12;
  solver.Solve(GaussianWindowResiduals{w, n_used}, &p);
  FitResult r;
  r.flux = p(0);
  r.u = p(1);
  r.v = p(2);
  r.sigma = p(3);
  r.background = p(4);
  r.ok = std::isfinite(r.u) && std::isfinite(r.v) && r.u >= x0 - 0.5 && r.u <= x1 + 0.5 && r.v >= y0 - 0.5 &&
         r.v <= y1 + 0.5;
  return r;
}

// Median of up to 9 values (small insertion sort).
float median_small(float* a, int n) {
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && a[j - 1] > a[j]; --j) std::swap(a[j - 1], a[j]);
  return n % 2 ? a[n / 2] : 0.5f * (a[n / 2 - 1] + a[n / 2]);
}

struct BlockGrid {
  int nbx = 0, nby = 0;  ///< blocks across and down
};

// 16×16 block max (ws.bmax) and mean (ws.bmean) over the whole image.
template <typename T>
BlockGrid block_stats(const cv::Mat& img, Workspace& ws) {
  const int W = img.cols, H = img.rows;
  const int nbx = (W + kBlock - 1) / kBlock, nby = (H + kBlock - 1) / kBlock;
  const std::size_t nb = static_cast<std::size_t>(nbx) * nby;
  ws.bmax.assign(nb, 0);
  ws.bsum.assign(nb, 0);
  ws.bmean.resize(nb);
#if defined(__SSE2__)
  if constexpr (sizeof(T) == 1)
    block_stats_u8_sse2(img, nbx, nby, ws);
  else
    block_stats_scalar<T>(img, nbx, nby, ws);
#else
  block_stats_scalar<T>(img, nbx, nby, ws);
#endif
  for (int by = 0; by < nby; ++by) {
    const int bh = std::min(H, (by + 1) * kBlock) - by * kBlock;
    for (int bx = 0; bx < nbx; ++bx) {
      const int bw = std::min(W, (bx + 1) * kBlock) - bx * kBlock;
      const std::size_t b = static_cast<std::size_t>(by) * nbx + bx;
      ws.bmean[b] = static_cast<float>(static_cast<double>(ws.bsum[b]) / (bw * bh));
    }
  }
  return {nbx, nby};
}

struct BlockHit {
  int bx, by;
  unsigned max;
  float background;
};

// ---- 3. candidate blocks: max > background + gate, background = median of the 3×3 block means;
// brightest first.
std::vector<BlockHit> candidate_blocks(const Workspace& ws, BlockGrid g, double gate, int max_candidates) {
  std::vector<BlockHit> hits;
  for (int by = 0; by < g.nby; ++by) {
    for (int bx = 0; bx < g.nbx; ++bx) {
      const std::size_t b = static_cast<std::size_t>(by) * g.nbx + bx;
      if (ws.bmax[b] <= ws.bmean[b] + gate) continue;
      float nb9[9] = {};  // k ≥ 1 (the block itself); zeroed for -Wmaybe-uninitialized
      int k = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = bx + dx, y = by + dy;
          if (x >= 0 && x < g.nbx && y >= 0 && y < g.nby)
            nb9[k++] = ws.bmean[static_cast<std::size_t>(y) * g.nbx + x];
        }
      const float bg = median_small(nb9, k);
      if (ws.bmax[b] > bg + gate) hits.push_back({bx, by, ws.bmax[b], bg});
    }
  }
  std::sort(hits.begin(), hits.end(), [](const BlockHit& a, const BlockHit& b) {
    return a.max != b.max ? a.max > b.max : (a.by != b.by ? a.by < b.by : a.bx < b.bx);
  });
  // Hot pixels are cheap to classify and must not crowd the lamp out, so the cap on examined
  // blocks is generous and only lamp-like candidates count towards max_candidates.
  if (hits.size() > static_cast<std::size_t>(16 * max_candidates)) hits.resize(16 * max_candidates);
  return hits;
}

struct Box {
  int x0, y0, x1, y1;
};

// ---- 4. seed = brightest pixel of the block (first in raster order).
template <typename T>
void brightest_pixel(const cv::Mat& img, const BlockHit& h, int* sx, int* sy) {
  const int bx0 = h.bx * kBlock, by0 = h.by * kBlock;
  const int bx1 = std::min(img.cols, bx0 + kBlock), by1 = std::min(img.rows, by0 + kBlock);
  *sx = bx0;
  *sy = by0;
  unsigned best = 0;
  for (int y = by0; y < by1; ++y) {
    const T* p = img.ptr<T>(y);
    for (int x = bx0; x < bx1; ++x)
      if (p[x] > best) {
        best = p[x];
        *sx = x;
        *sy = y;
      }
  }
}

// A blob grown from its seed: 8-connected pixels > the growth threshold within ±kGrowRadius.
struct Blob {
  int area = 0, n_sat = 0;
  int px = 0, py = 0;  ///< brightest pixel
  unsigned peak = 0;
  double sw = 0, swx = 0, swy = 0;  ///< Σ w, Σ w·x, Σ w·y with w = value − background
  bool extended = false;            ///< larger than max_blob_px or reaching past kGrowRadius
  Box box;                          ///< bounding box of the grown pixels
};

// ---- 4. grow the connected blob from (sx, sy) over pixels > thr.
template <typename T>
Blob grow_blob(const cv::Mat& img, int sx, int sy, double bg, double thr, int sat, int max_blob_px,
               Workspace& ws) {
  const int W = img.cols, H = img.rows;
  ws.stack.clear();
  ws.visited.clear();
  auto mask_at = [&](int x, int y) -> std::uint8_t& {
    return ws.mask[static_cast<std::size_t>((y - sy + kGrowRadius) * kGrowSide + (x - sx + kGrowRadius))];
  };
  mask_at(sx, sy) = 1;
  ws.stack.push_back(sy * W + sx);
  ws.visited.push_back(sy * W + sx);
  Blob b;
  b.px = sx;
  b.py = sy;
  b.box = {sx, sy, sx, sy};
  while (!ws.stack.empty()) {
    const int idx = ws.stack.back();
    ws.stack.pop_back();
    const int x = idx % W, y = idx / W;
    const unsigned val = img.ptr<T>(y)[x];
    ++b.area;
    if (static_cast<int>(val) >= sat) ++b.n_sat;
    if (val > b.peak) {
      b.peak = val;
      b.px = x;
      b.py = y;
    }
    const double w = val - bg;
    b.sw += w;
    b.swx += w * x;
    b.swy += w * y;
    b.box.x0 = std::min(b.box.x0, x);
    b.box.x1 = std::max(b.box.x1, x);
    b.box.y0 = std::min(b.box.y0, y);
    b.box.y1 = std::max(b.box.y1, y);
    if (b.area > max_blob_px) {
      b.extended = true;
      break;
    }
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
        if (std::abs(xx - sx) > kGrowRadius || std::abs(yy - sy) > kGrowRadius) {
          if (img.ptr<T>(yy)[xx] > thr) b.extended = true;
          continue;
        }
        std::uint8_t& m = mask_at(xx, yy);
        if (m || img.ptr<T>(yy)[xx] <= thr) continue;
        m = 1;
        ws.stack.push_back(yy * W + xx);
        ws.visited.push_back(yy * W + xx);
      }
  }
  for (const int idx : ws.visited) mask_at(idx % W, idx / W) = 0;
  return b;
}

// ---- 6. sub-pixel position of a lamp-like blob: the Gaussian fit (which may reclassify it by its
// σ), else the centroid of the saturated core, else c's intensity-weighted centroid stays.
template <typename T>
void subpixel_position(const cv::Mat& img, const Blob& blob, double bg, int sat, const LampDetectorOptions& o,
                       LampCandidate& c) {
  const int W = img.cols, H = img.rows;
  const int half = std::clamp(static_cast<int>(std::ceil(std::sqrt(blob.area / M_PI))) + 4, 6, 24);
  const int x0 = std::max(0, blob.px - half), x1 = std::min(W - 1, blob.px + half);
  const int y0 = std::max(0, blob.py - half), y1 = std::min(H - 1, blob.py + half);
  const double s0 = std::clamp(std::sqrt(std::max(blob.area, 1) / (2.0 * M_PI)) * 0.6, 0.7, 4.0);
  const FitResult f = fit_gaussian<T>(img, x0, x1, y0, y1, sat, c.u, c.v, s0, bg);
  if (f.ok) {
    c.u = f.u;
    c.v = f.v;
    c.sigma_px = f.sigma;
    c.fitted = true;
    if (f.sigma < o.min_sigma_px)
      c.kind = CandidateKind::hot_pixel;
    else if (f.sigma > o.max_sigma_px)
      c.kind = CandidateKind::extended;
  } else if (blob.n_sat > 0) {
    // Too few unsaturated pixels to fit: centroid of the saturated core.
    double su = 0, sv = 0;
    int n = 0;
    for (int y = blob.box.y0; y <= blob.box.y1; ++y)
      for (int x = blob.box.x0; x <= blob.box.x1; ++x)
        if (static_cast<int>(img.ptr<T>(y)[x]) >= sat) {
          su += x;
          sv += y;
          ++n;
        }
    if (n > 0) {
      c.u = su / n;
      c.v = sv / n;
    }
  }
}

// ---- 5. classify: extended, edge, hot pixel (small, or a lone spike), else lamp-like with a
// sub-pixel position (step 6) and low SNR below min_snr.
template <typename T>
LampCandidate classify_blob(const cv::Mat& img, const Blob& blob, double bg, double sigma, int sat,
                            const LampDetectorOptions& o) {
  const int W = img.cols, H = img.rows;
  const int px = blob.px, py = blob.py;
  LampCandidate c;
  c.background = bg;
  c.peak = blob.peak - bg;
  c.snr = c.peak / sigma;
  c.area = blob.area;
  c.saturated_px = blob.n_sat;
  c.u = blob.sw > 0 ? blob.swx / blob.sw : px;
  c.v = blob.sw > 0 ? blob.swy / blob.sw : py;
  if (blob.extended) {
    c.kind = CandidateKind::extended;
  } else if (px < o.edge_margin_px || py < o.edge_margin_px || px >= W - o.edge_margin_px ||
             py >= H - o.edge_margin_px) {
    c.kind = CandidateKind::edge;
  } else if (blob.area < o.min_area) {
    c.kind = CandidateKind::hot_pixel;
  } else {
    if (blob.n_sat == 0) {
      const double nmean = 0.25 * (static_cast<double>(img.ptr<T>(py)[px - 1]) + img.ptr<T>(py)[px + 1] +
                                   img.ptr<T>(py - 1)[px] + img.ptr<T>(py + 1)[px]) -
                           bg;
      if (nmean < o.min_neighbour_ratio * c.peak) c.kind = CandidateKind::hot_pixel;
    }
    if (c.kind == CandidateKind::lamp) {
      subpixel_position<T>(img, blob, bg, sat, o, c);
      if (c.kind == CandidateKind::lamp && c.snr < o.min_snr) c.kind = CandidateKind::low_snr;
    }
  }
  return c;
}

template <typename T>
FrameCandidates find_candidates_t(const cv::Mat& img, int bits, const LampDetectorOptions& o) {
  Workspace& ws = workspace();
  FrameCandidates fc;
  const int sat = (1 << bits) - 1;
  const double sigma = estimate_noise<T>(img, ws);
  fc.noise_sigma = sigma;
  const BlockGrid grid = block_stats<T>(img, ws);
  const std::vector<BlockHit> hits = candidate_blocks(ws, grid, o.k_detect * sigma, o.max_candidates);
  int n_lamp_like = 0;
  std::vector<Box> claimed;  // grown blobs (+1 px): a seed inside one is that blob again
  for (const BlockHit& h : hits) {
    int sx = 0, sy = 0;
    brightest_pixel<T>(img, h, &sx, &sy);
    bool inside = false;
    for (const Box& b : claimed)
      if (sx >= b.x0 && sx <= b.x1 && sy >= b.y0 && sy <= b.y1) inside = true;
    if (inside) continue;
    const double bg = h.background;
    const Blob blob = grow_blob<T>(img, sx, sy, bg, bg + o.k_grow * sigma, sat, o.max_blob_px, ws);
    claimed.push_back({blob.box.x0 - 1, blob.box.y0 - 1, blob.box.x1 + 1, blob.box.y1 + 1});
    const LampCandidate c = classify_blob<T>(img, blob, bg, sigma, sat, o);
    fc.candidates.push_back(c);
    if (c.kind != CandidateKind::hot_pixel && ++n_lamp_like >= o.max_candidates) break;
  }
  std::stable_sort(fc.candidates.begin(), fc.candidates.end(),
                   [](const LampCandidate& a, const LampCandidate& b) { return a.peak > b.peak; });
  return fc;
}

const char* status_of(CandidateKind k) {
  switch (k) {
    case CandidateKind::lamp:
      return lamp_status::kOk;
    case CandidateKind::hot_pixel:
      return lamp_status::kHotPixel;
    case CandidateKind::extended:
      return lamp_status::kExtended;
    case CandidateKind::edge:
      return lamp_status::kEdge;
    case CandidateKind::low_snr:
      return lamp_status::kLowSnr;
  }
  return lamp_status::kNoLamp;
}

int rejection_rank(CandidateKind k) {
  switch (k) {
    case CandidateKind::low_snr:
      return 4;
    case CandidateKind::edge:
      return 3;
    case CandidateKind::extended:
      return 2;
    case CandidateKind::hot_pixel:
      return 1;
    case CandidateKind::lamp:
      return 0;
  }
  return 0;
}

LampDetection row_from(const FrameCandidates& fc, const LampCandidate* c, const char* status) {
  LampDetection d;
  d.frame = fc.frame;
  d.utc = fc.utc;
  d.status = status;
  if (c) {
    d.u = c->u;
    d.v = c->v;
    d.peak = c->peak;
    d.area = c->area;
    d.snr = c->snr;
  }
  return d;
}

const char* ok_status(const LampCandidate& c) {
  return c.saturated_px > 0 ? lamp_status::kOkSaturated : lamp_status::kOk;
}

// ---- sequence pass -------------------------------------------------------------------------

// Static lights: lamp-like (or low-SNR) candidates that recur within static_radius_px in at least
// max(static_min_frames, static_min_fraction · loaded frames) frames. Per frame, per candidate.
std::vector<std::vector<bool>> static_lights(const std::vector<FrameCandidates>& frames,
                                             const LampDetectorOptions& o) {
  const std::size_t nf = frames.size();
  struct Pt {
    std::size_t f, c;
    double u, v;
  };
  std::vector<Pt> pts;
  std::size_t n_loaded = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    n_loaded += frames[f].loaded;
    for (std::size_t c = 0; c < frames[f].candidates.size(); ++c) {
      const auto k = frames[f].candidates[c].kind;
      if (k == CandidateKind::lamp || k == CandidateKind::low_snr)
        pts.push_back({f, c, frames[f].candidates[c].u, frames[f].candidates[c].v});
    }
  }
  const std::size_t need =
      std::max<std::size_t>(static_cast<std::size_t>(o.static_min_frames),
                            static_cast<std::size_t>(std::ceil(o.static_min_fraction * n_loaded)));
  const double cell = std::max(o.static_radius_px, 0.5);
  auto key = [](long cx, long cy) { return (static_cast<std::int64_t>(cx) << 32) ^ (cy & 0xFFFFFFFFll); };
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid;
  for (std::size_t i = 0; i < pts.size(); ++i)
    grid[key(static_cast<long>(std::floor(pts[i].u / cell)), static_cast<long>(std::floor(pts[i].v / cell)))]
        .push_back(i);
  std::vector<std::vector<bool>> is_static(nf);
  for (std::size_t f = 0; f < nf; ++f) is_static[f].assign(frames[f].candidates.size(), false);
  const double r2 = o.static_radius_px * o.static_radius_px;
  std::vector<std::size_t> seen_frames;
  for (const Pt& p : pts) {
    const long cx = static_cast<long>(std::floor(p.u / cell)), cy = static_cast<long>(std::floor(p.v / cell));
    seen_frames.clear();
    for (long dy = -1; dy <= 1 && seen_frames.size() < need; ++dy)
      for (long dx = -1; dx <= 1 && seen_frames.size() < need; ++dx) {
        const auto it = grid.find(key(cx + dx, cy + dy));
        if (it == grid.end()) continue;
        for (const std::size_t j : it->second) {
          const Pt& q = pts[j];
          if ((q.u - p.u) * (q.u - p.u) + (q.v - p.v) * (q.v - p.v) > r2) continue;
          if (std::find(seen_frames.begin(), seen_frames.end(), q.f) == seen_frames.end()) {
            seen_frames.push_back(q.f);
            if (seen_frames.size() >= need) break;
          }
        }
      }
    if (seen_frames.size() >= need) is_static[p.f][p.c] = true;
  }
  return is_static;
}

// Per-frame status: the one non-static lamp candidate, else ambiguous, else the most lamp-like
// rejection. *lamps receives the indices of the non-static lamp candidates.
LampDetection frame_status(const FrameCandidates& fc, const std::vector<bool>& is_static,
                           std::vector<std::size_t>* lamps) {
  if (!fc.loaded) return row_from(fc, nullptr, lamp_status::kMissingFrame);
  for (std::size_t c = 0; c < fc.candidates.size(); ++c)
    if (fc.candidates[c].kind == CandidateKind::lamp && !is_static[c]) lamps->push_back(c);
  if (lamps->size() == 1) {
    const LampCandidate& c = fc.candidates[(*lamps)[0]];
    return row_from(fc, &c, ok_status(c));
  }
  if (lamps->size() > 1) return row_from(fc, &fc.candidates[(*lamps)[0]], lamp_status::kAmbiguous);
  if (fc.candidates.empty()) return row_from(fc, nullptr, lamp_status::kNoLamp);
  // Report the most lamp-like rejection (static > low SNR > edge > extended > hot pixel), its
  // strongest candidate.
  std::size_t best = 0;
  int best_rank = -1;
  for (std::size_t c = 0; c < fc.candidates.size(); ++c) {
    const int rank = is_static[c] ? 5 : rejection_rank(fc.candidates[c].kind);
    if (rank > best_rank) {
      best_rank = rank;
      best = c;
    }
  }
  return row_from(fc, &fc.candidates[best],
                  is_static[best] ? lamp_status::kStatic : status_of(fc.candidates[best].kind));
}

// The two anchor frames (unambiguous detections within motion_max_gap_s) that predict frame f
// linearly in time: the nearest before and after, else the two nearest on one side. False when
// there are not two.
bool motion_anchors(const std::vector<FrameCandidates>& frames, const std::vector<bool>& anchor,
                    std::size_t f, std::int64_t max_gap_ns, std::size_t* a, std::size_t* b) {
  const std::size_t nf = frames.size();
  std::vector<std::size_t> before, after;
  for (std::size_t g = f; g-- > 0 && before.size() < 2;) {
    if (frames[f].utc.ns - frames[g].utc.ns > max_gap_ns) break;
    if (anchor[g]) before.push_back(g);
  }
  for (std::size_t g = f + 1; g < nf && after.size() < 2; ++g) {
    if (frames[g].utc.ns - frames[f].utc.ns > max_gap_ns) break;
    if (anchor[g]) after.push_back(g);
  }
  if (!before.empty() && !after.empty()) {
    *a = before[0];
    *b = after[0];
  } else if (before.size() == 2) {
    *a = before[1];
    *b = before[0];
  } else if (after.size() == 2) {
    *a = after[0];
    *b = after[1];
  } else {
    return false;
  }
  return true;
}

// Motion consistency for frames with several candidates: predict the lamp from the nearest
// unambiguous detections before/after (linear in time) and keep the candidate that agrees — only
// when exactly one does.
void resolve_by_motion(const std::vector<FrameCandidates>& frames,
                       const std::vector<std::vector<std::size_t>>& lamps, const LampDetectorOptions& o,
                       std::vector<LampDetection>& out) {
  const std::size_t nf = frames.size();
  std::vector<bool> anchor(nf);
  for (std::size_t f = 0; f < nf; ++f)
    anchor[f] = out[f].status == lamp_status::kOk || out[f].status == lamp_status::kOkSaturated;
  const std::int64_t max_gap_ns = static_cast<std::int64_t>(o.motion_max_gap_s * 1e9);
  for (std::size_t f = 0; f < nf; ++f) {
    if (lamps[f].size() < 2) continue;
    std::size_t a = nf, b = nf;
    if (!motion_anchors(frames, anchor, f, max_gap_ns, &a, &b)) continue;  // cannot predict: stays ambiguous
    const double ta = static_cast<double>(frames[a].utc.ns - frames[f].utc.ns);
    const double tb = static_cast<double>(frames[b].utc.ns - frames[f].utc.ns);
    const double w = ta / (ta - tb);  // position at f = A + (B − A)·(0 − ta)/(tb − ta)
    const double pu = out[a].u + (out[b].u - out[a].u) * w;
    const double pv = out[a].v + (out[b].v - out[a].v) * w;
    double d1 = 1e300, d2 = 1e300;
    std::size_t best = 0;
    for (const std::size_t c : lamps[f]) {
      const LampCandidate& lc = frames[f].candidates[c];
      const double d = std::hypot(lc.u - pu, lc.v - pv);
      if (d < d1) {
        d2 = d1;
        d1 = d;
        best = c;
      } else if (d < d2) {
        d2 = d;
      }
    }
    if (d1 <= o.motion_gate_px && d2 > 2.0 * o.motion_gate_px)
      out[f] = row_from(frames[f], &frames[f].candidates[best], lamp_status::kOkByMotion);
  }
}

}  // namespace

FrameCandidates find_lamp_candidates(const cv::Mat& image, int bits, const LampDetectorOptions& options) {
  if (image.empty() || image.channels() != 1 || (image.depth() != CV_8U && image.depth() != CV_16U))
    throw std::invalid_argument("find_lamp_candidates: expected a CV_8UC1 or CV_16UC1 image");
  if (image.depth() == CV_8U) return find_candidates_t<std::uint8_t>(image, std::min(bits, 8), options);
  return find_candidates_t<std::uint16_t>(image, bits, options);
}

std::vector<LampDetection> resolve_lamp_sequence(const std::vector<FrameCandidates>& frames,
                                                 const LampDetectorOptions& o) {
  const std::size_t nf = frames.size();
  const std::vector<std::vector<bool>> is_static = static_lights(frames, o);
  std::vector<LampDetection> out(nf);
  std::vector<std::vector<std::size_t>> lamps(nf);
  for (std::size_t f = 0; f < nf; ++f) out[f] = frame_status(frames[f], is_static[f], &lamps[f]);
  resolve_by_motion(frames, lamps, o, out);
  return out;
}

namespace {

int arena_threads(int threads) {
  return threads > 0 ? threads : tbb::task_arena::automatic;
}

}  // namespace

std::vector<LampDetection> detect_lamp(const FrameSource& source, const std::vector<std::size_t>& indices,
                                       const LampDetectorOptions& options, int threads,
                                       const std::function<void()>& on_frame_done) {
  const std::size_t n = indices.size();
  std::vector<FrameCandidates> fcs(n);
  std::vector<std::exception_ptr> errors(n);
  tbb::task_arena arena(arena_threads(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          try {
                            const FrameTimestamp& e = source.entry(indices[i]);
                            std::string reason;
                            const auto frame = source.load(indices[i], &reason);
                            if (frame) {
                              fcs[i] = find_lamp_candidates(frame->image, frame->bits, options);
                            } else {
                              fcs[i].loaded = false;
                              fcs[i].skip_reason = reason;
                            }
                            fcs[i].frame = e.frame;
                            fcs[i].utc = e.utc;
                          } catch (...) {
                            errors[i] = std::current_exception();
                          }
                          if (on_frame_done) on_frame_done();
                        }
                      });
  });
  // The first failing frame in order, whatever the thread count.
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return resolve_lamp_sequence(fcs, options);
}

std::vector<LampDetection> detect_lamp(const std::vector<ImageFrame>& frames,
                                       const LampDetectorOptions& options, int threads) {
  const std::size_t n = frames.size();
  std::vector<FrameCandidates> fcs(n);
  tbb::task_arena arena(arena_threads(threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          fcs[i] = find_lamp_candidates(frames[i].image, frames[i].bits, options);
                          fcs[i].frame = frames[i].frame;
                          fcs[i].utc = frames[i].utc;
                        }
                      });
  });
  return resolve_lamp_sequence(fcs, options);
}

}  // namespace rangecal

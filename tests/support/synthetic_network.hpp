#pragma once
// A synthetic network for the network bundle's tests and benchmarks (optim/network): seed-002-like
// range cameras (1280×800, 20 µm, 135 mm) on a 64 m circle round a lamp volume 5 m × 5 m × 4 m
// (centred 20 m above their tripods' level + 18.5 m), each epoch seen by every camera it falls in,
// PPK fixes with 1 cm noise per axis, 0.05 px centroids. The cameras start off the truth by 2–4 cm,
// 0.3 mrad and f × 1.002, as from a per-camera bundle. Deterministic by seed.
#include <cstdint>
#include <optional>
#include <vector>

#include "optim/network/network_adjustment.hpp"
#include "optim/network/network_parameters.hpp"

namespace rangecal::test {

struct SyntheticNetwork {
  std::vector<Camera> truth;
  std::vector<NetworkCamera> cameras;  ///< free f, k1, pose
  std::vector<NetworkPoint> points;    ///< epochs seen by at least one camera
  std::vector<NetworkObservation> observations;
};

SyntheticNetwork synthetic_network(int n_cameras, int n_epochs, std::uint64_t seed);

/// A synthetic network laid out for the network's steps (optim/network/network_parameters.hpp).
/// The layout points into `data`: build it in place (lay_out_network) and do not copy it.
struct NetworkScene {
  SyntheticNetwork data;
  NetworkLayout layout;
  NetworkParameterBlocks blocks;
  NetworkSelection selection;
};

/// Lays out `scene->data` as it stands: the starting blocks (every camera's clock at `clock_s` when
/// given), every observation and prior selected, the single-view weights at the starting cameras.
void lay_out_network(NetworkScene* scene, std::optional<double> clock_s = std::nullopt);

}  // namespace rangecal::test

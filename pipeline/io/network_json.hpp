#pragma once
// `<out>/network.json` (docs/optimisation.md "Network bundle"): the network's statistics and the
// joint covariance of every camera's free parameters — the per-camera blocks are each camera's
// calibration.json covariance, the cross blocks what the intersection needs to know that the
// cameras are correlated. Keys: method, cameras [{id, parameters}], joint_covariance (rows, cameras
// in order), statistics {variance_factor, chi2, dof, epochs_seen_by_1/2/3_or_more, ppk_outliers
// (utc), image_outliers, float_epochs_used, cameras_alone}, datum_floor {image_factor, joint_covariance}
// (the same matrix with every image σ divided by image_factor), and when float epochs were used
// float_epochs {epochs, cameras [{id, parameters, sigma_with, sigma_without (null when the cameras
// are undetermined without them)}]} — what they add (docs/optimisation.md, "Float epochs").
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnss/track/ppk_error_model_json.hpp"
#include "optim/network/network_result.hpp"
#include "vision/triangulation/triangulation.hpp"

namespace rangecal {

/// The estimate of the model from the mission (PpkErrorEstimate; docs/outputs.md): each parameter's
/// σ (null where held), whether the white model was kept, the likelihood ratio, the record length
/// and which τ were held at the fallback (optim/network/ppk_error_estimation.hpp).
nlohmann::json ppk_error_estimate_json(const PpkErrorEstimate& estimate);
/// Each camera's lamp-centroid σ (px) estimated with the model: {id: {stated_px, estimated_px,
/// sd_px}} — the image variance components (docs/optimisation.md "Image variance components"); the
/// statistics' `image_sigma` when the network estimated them.
nlohmann::json image_sigma_json(const NetworkResult& r);
/// The statistics object (also run.json's `network` counts). `epoch_utc` names each point's epoch
/// ("" for poles).
nlohmann::json network_statistics_json(const NetworkResult& r, const std::vector<std::string>& epoch_utc);

/// `ppk_error_model` read back (the report's PPK error model section): the model, each value's σ
/// where the writer gives one (a `sigma` {`horizontal`, `vertical`} beside the value: estimated;
/// absent: NaN, the value fixed in the config), and for a correlated model its chained epochs and
/// independent looks (NaN when not written).
struct PpkErrorModelRecord {
  PpkErrorModel model;
  PpkErrorModel sigma{std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan(""), std::nan("")};
  long states = 0;
  double looks_h = std::nan(""), looks_v = std::nan("");
  bool estimated = false;  ///< `estimate` present: sigma from its `sd` (NaN where held)
  bool white_kept = false;
  bool gm_sd_held_h = false, gm_sd_held_v = false;  ///< σ_g held at the .pos sd: a short record
  double record_s = std::nan("");
};

/// Parses `j` as written by ppk_error_model_json (with `independent_looks`); `path` and `field` name
/// it in messages: a missing or unknown key, a value of the wrong type or outside the model's limits
/// (gnss/track/ppk_error_model_json.hpp) throws rangecal::Error (input) naming `field.<key>`.
PpkErrorModelRecord parse_ppk_error_model_json(const nlohmann::json& j, const std::string& path,
                                               const std::string& field);

/// The statistics object read back (the report's network section): NetworkStatistics with the PPK
/// outliers and the cameras alone by name.
struct NetworkStatisticsRecord {
  double variance_factor = 0;  ///< χ²/dof; NaN when written as null (no redundancy)
  double chi2 = 0;
  long dof = 0;
  long epochs_seen_by_1 = 0, epochs_seen_by_2 = 0, epochs_seen_by_3_or_more = 0;
  long float_epochs_used = 0;
  std::vector<std::string> ppk_outliers;  ///< UTC of each flagged epoch
  long image_outliers = 0;
  std::vector<std::string> cameras_alone;  ///< camera ids
  bool rank_deficient = false;
  /// `ppk_error_model`; absent when the object has none (written before the network carried it).
  std::optional<PpkErrorModelRecord> ppk_error_model;
};

/// Parses `j` as written by network_statistics_json. `path` and `field` (the object's JSON path,
/// e.g. "stages.calibrate.counts.network") name it in messages: a missing key or a value of the
/// wrong type throws rangecal::Error (input) naming `field.<key>`.
NetworkStatisticsRecord parse_network_statistics_json(const nlohmann::json& j, const std::string& path,
                                                      const std::string& field);

/// network.json's `statistics.image_sigma`: each camera's estimated image σ per axis (px) by id;
/// empty when the file or the object is absent (a network written without image variance components).
/// A malformed entry throws rangecal::Error (input) naming the file and field.
std::map<std::string, double> read_network_image_sigma(const std::string& path);

/// network.json's `float_epochs` read back: each camera's a-priori σ (its parameters' units, in
/// `parameters` order) with the float epochs and without them.
struct FloatEpochsRecord {
  struct Camera {
    std::string id;
    std::vector<CameraParameter> parameters;
    std::vector<double> sigma_with;
    std::vector<double> sigma_without;  ///< empty: undetermined without the float epochs
  };
  long epochs = 0;
  std::vector<Camera> cameras;
};

/// `float_epochs` of network.json at `path`; nullopt when the file is missing or has none. Throws
/// rangecal::Error (input) naming `float_epochs.<key>` for a malformed object.
std::optional<FloatEpochsRecord> read_network_float_epochs(const std::string& path);

/// network.json's `statistics.ppk_error_model` at `path`: the model the network weighed the fixes by;
/// nullopt when the file is missing or has none (written before the network carried it). Throws
/// rangecal::Error (input) naming `statistics.ppk_error_model.<key>` for a malformed object.
std::optional<PpkErrorModelRecord> read_network_ppk_error_model(const std::string& path);

/// network.json's text.
nlohmann::json network_json(const NetworkResult& r, const std::vector<std::string>& epoch_utc);
void write_network_json(const std::string& path, const nlohmann::json& j);

/// network.json's `datum_floor` (optim/network/network_options.hpp kDatumFloorImageFactor): the
/// joint covariance with every image σ divided by `image_factor`, as camera-pair blocks.
struct NetworkDatumFloor {
  double image_factor = 0;
  CrossCovariances blocks;  ///< [a][b] for the cameras asked for, diagonal blocks included
};

/// `datum_floor` of network.json at `path` for the cameras `ids`, blocks as
/// read_network_cross_covariances gives them but with the diagonal (each camera's own floor);
/// nullopt when the file is missing, has none, or does not match the cameras. Throws rangecal::Error
/// (input) naming `datum_floor.<key>` for a malformed object.
std::optional<NetworkDatumFloor> read_network_datum_floor(
    const std::string& path, const std::vector<std::string>& ids,
    const std::vector<std::vector<CameraParameter>>* parameters = nullptr);

/// The cross blocks for the cameras `ids` (in the views' order) read from network.json; empty
/// when the file is missing, a camera is not in it, or it has no joint covariance. When
/// `parameters` is given (one list per id: the parameters of that camera's calibration.json
/// covariance), each block is returned in those orders, and the table is empty when a camera's
/// network parameters are not the same set (network.json is then not the calibration's). Throws
/// rangecal::Error (input) for a malformed file.
CrossCovariances read_network_cross_covariances(
    const std::string& path, const std::vector<std::string>& ids,
    const std::vector<std::vector<CameraParameter>>* parameters = nullptr);

}  // namespace rangecal

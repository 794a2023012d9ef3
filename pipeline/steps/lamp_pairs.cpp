#include "pipeline/steps/lamp_pairs.hpp"

namespace rangecal {

std::vector<Correspondence> lamp_pairs(const std::vector<AlignedFrame>& aligned,
                                       const std::vector<LampDetection>& det) {
  std::vector<Correspondence> pairs;
  for (std::size_t i = 0; i < det.size() && i < aligned.size(); ++i) {
    if (!det[i].usable()) continue;
    Correspondence c;
    c.utc = aligned[i].utc;
    c.enu = aligned[i].enu;
    c.sd_enu = aligned[i].sd_enu;
    c.vel_enu = aligned[i].vel_enu;
    c.uv = {det[i].u, det[i].v};
    pairs.push_back(c);
  }
  return pairs;
}

}  // namespace rangecal

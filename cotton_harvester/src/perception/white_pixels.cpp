#include <algorithm>

#include <opencv2/core/hal/intrin.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"

namespace cotton_harvester {
namespace perception {

cv::Mat whitePixels(const cv::Mat& bgr, int value_min, int saturation_max) {
  // HSV value V = max(b, g, r) and saturation S = 255 (V - min(b, g, r)) / V without the conversion:
  // S <= saturation_max  <=>  255 (V - min) <= saturation_max V. Both sides are at most 255^2: 16-bit lanes hold them.
  CV_Assert(bgr.type() == CV_8UC3);
  value_min = std::clamp(value_min, 0, 255);
  saturation_max = std::clamp(saturation_max, 0, 255);
  cv::Mat mask(bgr.size(), CV_8U);
  for (int v = 0; v < bgr.rows; ++v) {
    const uint8_t* pixel = bgr.ptr<uint8_t>(v);
    uint8_t* out = mask.ptr<uint8_t>(v);
    int u = 0;
#if CV_SIMD128
    // Sixteen pixels at a time; the same test as below, bit for bit.
    const cv::v_uint8x16 value_floor = cv::v_setall_u8(static_cast<uint8_t>(value_min));
    const cv::v_uint16x8 full = cv::v_setall_u16(255), share = cv::v_setall_u16(static_cast<uint16_t>(saturation_max));
    for (; u + 16 <= bgr.cols; u += 16, pixel += 48) {
      cv::v_uint8x16 b, g, r;
      cv::v_load_deinterleave(pixel, b, g, r);
      const cv::v_uint8x16 high = cv::v_max(b, cv::v_max(g, r));
      const cv::v_uint8x16 low = cv::v_min(b, cv::v_min(g, r));
      cv::v_uint16x8 high0, high1, low0, low1;
      cv::v_expand(high, high0, high1);
      cv::v_expand(low, low0, low1);
      // Wrapping products (neither exceeds 255^2); a <= b as the saturating a - b being 0.
      const cv::v_uint16x8 zero = cv::v_setzero_u16();
      const cv::v_uint16x8 grey0 = (cv::v_mul_wrap(high0 - low0, full) - cv::v_mul_wrap(high0, share)) == zero;
      const cv::v_uint16x8 grey1 = (cv::v_mul_wrap(high1 - low1, full) - cv::v_mul_wrap(high1, share)) == zero;
      cv::v_store(out + u, cv::v_pack(grey0, grey1) & (high >= value_floor));
    }
#endif
    for (; u < bgr.cols; ++u, pixel += 3) {
      const int high = std::max({pixel[0], pixel[1], pixel[2]});
      const int low = std::min({pixel[0], pixel[1], pixel[2]});
      out[u] = (high >= value_min && 255 * (high - low) <= saturation_max * high) ? 255 : 0;
    }
  }
  return mask;
}

}  // namespace perception
}  // namespace cotton_harvester

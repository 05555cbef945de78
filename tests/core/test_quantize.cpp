// SPDX-License-Identifier: MIT
// UNORM quantization: the round trip error bound, clamping, NaN, and the range quantizer.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include <cellrelief/core/quantize.h>

namespace cellrelief {
namespace {

template <class U>
void expectHalfStepRoundTrip() {
  const double halfStep = 0.5 * unormStep<U>();
  double worst = 0;
  for (int i = 0; i <= 1000000; ++i) {
    const double x = i / 1000000.0;
    const double back = dequantizeUnorm<U, double>(quantizeUnorm<U>(x));
    worst = std::max(worst, std::abs(back - x));
  }
  EXPECT_LE(worst, halfStep * (1 + 1e-9));
  EXPECT_GT(worst, 0.9 * halfStep);  // the bound is tight, not loose
}

TEST(Quantize, RoundTripWithinHalfAStep8Bit) { expectHalfStepRoundTrip<std::uint8_t>(); }
TEST(Quantize, RoundTripWithinHalfAStep16Bit) { expectHalfStepRoundTrip<std::uint16_t>(); }

TEST(Quantize, EndpointsAreExactAndOutOfRangeClamps) {
  EXPECT_EQ(quantizeUnorm<std::uint8_t>(0.0f), 0);
  EXPECT_EQ(quantizeUnorm<std::uint8_t>(1.0f), 255);
  EXPECT_EQ(quantizeUnorm<std::uint16_t>(1.0), 65535);
  EXPECT_EQ(quantizeUnorm<std::uint8_t>(-3.0f), 0);
  EXPECT_EQ(quantizeUnorm<std::uint8_t>(7.0f), 255);
  EXPECT_EQ(quantizeUnorm<std::uint16_t>(std::numeric_limits<float>::infinity()), 65535);
  EXPECT_EQ(quantizeUnorm<std::uint16_t>(-std::numeric_limits<float>::infinity()), 0);
  EXPECT_EQ(quantizeUnorm<std::uint16_t>(std::nanf("")), 0);
  EXPECT_EQ(dequantizeUnorm<std::uint8_t>(std::uint8_t(255)), 1.0f);
  EXPECT_EQ(dequantizeUnorm<std::uint8_t>(std::uint8_t(0)), 0.0f);
}

TEST(Quantize, EveryCodeRoundTripsExactly) {
  for (int q = 0; q <= 65535; ++q)
    ASSERT_EQ(quantizeUnorm<std::uint16_t>(dequantizeUnorm<std::uint16_t>(std::uint16_t(q))), q);
}

TEST(Quantize, RangeQuantizerMeetsItsStatedError) {
  const RangeQuantizer<std::uint16_t, double> q{-0.25, 3.75};
  double worst = 0;
  for (int i = 0; i <= 200000; ++i) {
    const double x = -0.25 + 4.0 * i / 200000.0;
    worst = std::max(worst, std::abs(q.decode(q.encode(x)) - x));
  }
  EXPECT_LE(worst, q.maxError() * (1 + 1e-9));
  EXPECT_NEAR(q.maxError(), 4.0 / (2 * 65535.0), 1e-15);
}

}  // namespace
}  // namespace cellrelief

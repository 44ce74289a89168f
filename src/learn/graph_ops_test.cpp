// TF semantics of the tricky ops against hand-computed values (and, for convolutions, against
// a direct loop over TF's definition).

#include "learn/graph_ops.h"

#include <gtest/gtest.h>

#include <vector>

namespace wheelpose::learn::ops {
namespace {

using torch::Tensor;

std::vector<float> values(const Tensor& t) {
  const Tensor c = t.detach().to(torch::kFloat).contiguous();
  return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}
std::vector<std::int64_t> ivalues(const Tensor& t) { return int_values(t); }
std::vector<std::int64_t> shape(const Tensor& t) { return t.sizes().vec(); }

// 1×h×w×1 NHWC holding 1, 2, 3, ... row-major.
Tensor counting_image(std::int64_t h, std::int64_t w) {
  return torch::arange(1, h * w + 1, torch::kFloat).reshape({1, h, w, 1});
}

void expect_near(const std::vector<float>& got, const std::vector<float>& want, float tol = 1e-5f) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], tol) << "at " << i;
}

ConvSpec same_stride(std::int64_t s) {
  ConvSpec spec;
  spec.stride = {s, s};
  spec.padding.kind = Padding::Kind::kSame;
  return spec;
}

TEST(SamePadding, MatchesTfFormula) {
  // pad_total = max((ceil(in/s) - 1) * s + (k - 1) * d + 1 - in, 0); before = total / 2.
  EXPECT_EQ(same_padding(4, 3, 2, 1), (std::pair<std::int64_t, std::int64_t>{0, 1}));
  EXPECT_EQ(same_padding(5, 3, 2, 1), (std::pair<std::int64_t, std::int64_t>{1, 1}));
  EXPECT_EQ(same_padding(5, 2, 2, 1), (std::pair<std::int64_t, std::int64_t>{0, 1}));
  EXPECT_EQ(same_padding(256, 3, 2, 1), (std::pair<std::int64_t, std::int64_t>{0, 1}));
  EXPECT_EQ(same_padding(7, 3, 1, 2), (std::pair<std::int64_t, std::int64_t>{2, 2}));
  EXPECT_EQ(same_padding(6, 4, 1, 1), (std::pair<std::int64_t, std::int64_t>{1, 2}));
  EXPECT_EQ(same_padding(3, 1, 4, 1), (std::pair<std::int64_t, std::int64_t>{0, 0}));
}

// Both memory layouts must give the same numbers.
class ConvLayouts : public ::testing::TestWithParam<bool> {};

TEST_P(ConvLayouts, SameStride2EvenInputPadsOnlyAfter) {
  // 4×4 input, 3×3 ones, stride 2: TF pads 0 before and 1 after; a symmetric pad of 1 would
  // make the first output 1+2+5+6 = 14.
  const Tensor filter = torch::ones({3, 3, 1, 1});
  const Tensor y = conv2d_nhwc(counting_image(4, 4), filter, {}, {}, same_stride(2), GetParam());
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{1, 2, 2, 1}));
  expect_near(values(y), {54, 45, 72, 54});
}

TEST_P(ConvLayouts, SameStride2OddInputPadsBothSides) {
  const Tensor filter = torch::ones({3, 3, 1, 1});
  const Tensor y = conv2d_nhwc(counting_image(5, 5), filter, {}, {}, same_stride(2), GetParam());
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{1, 3, 3, 1}));
  expect_near(values(y), {16, 33, 28, 69, 117, 87, 76, 123, 88});
}

TEST_P(ConvLayouts, SameStride2OddInputEvenKernelPadsAfter) {
  // 5×5, 2×2 ones, stride 2: out 3, pad_total 1 -> (0, 1).
  const Tensor filter = torch::ones({2, 2, 1, 1});
  const Tensor y = conv2d_nhwc(counting_image(5, 5), filter, {}, {}, same_stride(2), GetParam());
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{1, 3, 3, 1}));
  // rows {0,1},{2,3},{4}; cols likewise.
  expect_near(values(y), {1 + 2 + 6 + 7, 3 + 4 + 8 + 9, 5 + 10, 11 + 12 + 16 + 17,
                          13 + 14 + 18 + 19, 15 + 20, 21 + 22, 23 + 24, 25});
}

TEST_P(ConvLayouts, FusedBiasAndRelu6) {
  ConvSpec spec = same_stride(1);
  spec.bias = true;
  spec.activation = Activation::kRelu6;
  // 1×1 conv, 1 -> 2 channels: x*1 - 3 and x*(-1) + 20, clipped to [0, 6].
  const Tensor filter = torch::tensor({1.0f, -1.0f}).reshape({1, 1, 1, 2});
  const Tensor bias = torch::tensor({-3.0f, 20.0f});
  const Tensor y = conv2d_nhwc(counting_image(1, 4), filter, bias, {}, spec, GetParam());
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{1, 1, 4, 2}));
  expect_near(values(y), {0, 6, 0, 6, 0, 6, 1, 6});
}

TEST_P(ConvLayouts, DepthwiseMultiplierOrdersChannelsLikeTf) {
  // 3×3×2 input: channel 0 = 1..9, channel 1 = 10..90. Filter [3, 3, 2, 2]:
  // (c0, m0) all ones, (c0, m1) centre 1, (c1, m0) centre 2, (c1, m1) all -1.
  // TF's output channel order is c * multiplier + m.
  const Tensor c0 = torch::arange(1, 10, torch::kFloat).reshape({1, 3, 3, 1});
  const Tensor x = torch::cat({c0, c0 * 10}, 3);
  Tensor f = torch::zeros({3, 3, 2, 2});
  f.index_put_({torch::indexing::Slice(), torch::indexing::Slice(), 0, 0}, 1.0f);
  f.index_put_({1, 1, 0, 1}, 1.0f);
  f.index_put_({1, 1, 1, 0}, 2.0f);
  f.index_put_({torch::indexing::Slice(), torch::indexing::Slice(), 1, 1}, -1.0f);
  ConvSpec spec = same_stride(1);
  spec.depthwise = true;
  const Tensor y = conv2d_nhwc(x, f, {}, {}, spec, GetParam());
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{1, 3, 3, 4}));
  // Pixel (0, 0): neighbourhood {1, 2, 4, 5}; pixel (1, 1): all nine.
  expect_near(values(y.select(1, 0).select(1, 0)), {12, 1, 20, -120});
  expect_near(values(y.select(1, 1).select(1, 1)), {45, 5, 100, -450});
  // The torch-layout filter gives the same.
  spec.filter_in_torch_layout = true;
  const Tensor y2 = conv2d_nhwc(x, depthwise_filter_to_torch(f), {}, {}, spec, GetParam());
  EXPECT_TRUE(torch::equal(y, y2));
}

// TF's convolution by its definition: out[b, i, j, o] = sum x[b, i*s + di*d - pad_top, ...].
Tensor reference_conv(const Tensor& x, const Tensor& f, std::int64_t stride, std::int64_t dil,
                      bool depthwise) {
  const std::int64_t h = x.size(1), w = x.size(2), cin = x.size(3);
  const std::int64_t kh = f.size(0), kw = f.size(1), m = f.size(3);
  const auto [pt, pb] = same_padding(h, kh, stride, dil);
  const auto [pl, pr] = same_padding(w, kw, stride, dil);
  const std::int64_t oh = (h + pt + pb - ((kh - 1) * dil + 1)) / stride + 1;
  const std::int64_t ow = (w + pl + pr - ((kw - 1) * dil + 1)) / stride + 1;
  const std::int64_t cout = depthwise ? cin * m : m;
  Tensor out = torch::zeros({1, oh, ow, cout}, torch::kDouble);
  const Tensor xd = x.to(torch::kDouble), fd = f.to(torch::kDouble);
  auto xa = xd.accessor<double, 4>();
  auto fa = fd.accessor<double, 4>();
  auto oa = out.accessor<double, 4>();
  for (std::int64_t i = 0; i < oh; ++i)
    for (std::int64_t j = 0; j < ow; ++j)
      for (std::int64_t a = 0; a < kh; ++a)
        for (std::int64_t b = 0; b < kw; ++b) {
          const std::int64_t y = i * stride + a * dil - pt, xx = j * stride + b * dil - pl;
          if (y < 0 || y >= h || xx < 0 || xx >= w) continue;
          for (std::int64_t c = 0; c < cin; ++c) {
            if (depthwise) {
              for (std::int64_t q = 0; q < m; ++q)
                oa[0][i][j][c * m + q] += xa[0][y][xx][c] * fa[a][b][c][q];
            } else {
              for (std::int64_t o = 0; o < cout; ++o)
                oa[0][i][j][o] += xa[0][y][xx][c] * fa[a][b][c][o];
            }
          }
        }
  return out.to(torch::kFloat);
}

TEST_P(ConvLayouts, MatchesTfDefinitionOnRandomInputs) {
  torch::manual_seed(7);
  struct Case {
    std::int64_t h, w, k, stride, dil;
    bool depthwise;
  };
  for (const Case& c : std::vector<Case>{{8, 8, 3, 2, 1, false},
                                         {9, 7, 3, 2, 1, false},
                                         {10, 11, 5, 2, 1, true},
                                         {7, 6, 3, 1, 2, true},
                                         {6, 9, 4, 3, 1, false},
                                         {12, 12, 3, 2, 1, true}}) {
    const std::int64_t cin = 3, m = c.depthwise ? 2 : 4;
    const Tensor x = torch::randn({1, c.h, c.w, cin});
    const Tensor f = torch::randn({c.k, c.k, cin, m});
    ConvSpec spec = same_stride(c.stride);
    spec.dilation = {c.dil, c.dil};
    spec.depthwise = c.depthwise;
    const Tensor got = conv2d_nhwc(x, f, {}, {}, spec, GetParam());
    const Tensor want = reference_conv(x, f, c.stride, c.dil, c.depthwise);
    ASSERT_EQ(shape(got), shape(want)) << c.h << "x" << c.w << " k" << c.k;
    EXPECT_LT((got - want).abs().max().item<float>(), 1e-4f) << c.h << "x" << c.w << " k" << c.k;
  }
}

INSTANTIATE_TEST_SUITE_P(Memory, ConvLayouts, ::testing::Values(true, false),
                         [](const auto& info) { return info.param ? "ChannelsLast" : "Nchw"; });

TEST(MaxPool, SamePaddingNeverWins) {
  // All negative values: a zero pad would win at the borders, TF's excluded pad does not.
  const Tensor x = -counting_image(4, 4);
  Padding same;
  same.kind = Padding::Kind::kSame;
  const Tensor y = max_pool_nhwc(x, {3, 3}, {2, 2}, same, true);  // pads (0, 1): asymmetric
  expect_near(values(y), {-1, -3, -9, -11});
  const Tensor z = max_pool_nhwc(x, {5, 5}, {1, 1}, same, false);  // pads (2, 2)
  EXPECT_EQ(values(z)[0], -1);
  EXPECT_EQ(values(z)[15], -6);  // (3, 3): window rows and cols 1..4
  EXPECT_EQ(values(z)[10], -1);
}

// 1×1×4×1 holding 0, 10, 20, 30, resized to width 8.
Tensor ramp() { return torch::tensor({0.0f, 10.0f, 20.0f, 30.0f}).reshape({1, 1, 4, 1}); }

TEST(ResizeBilinear, HalfPixelCentersUpsample) {
  // src = (dst + 0.5) * 0.5 - 0.5; below 0 and above 3 clamp to the edge.
  const std::vector<float> want = {0, 2.5, 7.5, 12.5, 17.5, 22.5, 27.5, 30};
  expect_near(values(resize_bilinear(ramp(), 1, 8, false, true)), want);
  expect_near(values(resize_bilinear_reference(ramp(), 1, 8, false, true)), want);
}

TEST(ResizeBilinear, HalfPixelCentersDownsample) {
  // 4 -> 3: src = (dst + 0.5) * 4/3 - 0.5 = 1/6, 3/2, 17/6.
  const std::vector<float> want = {10.0f / 6, 15, 170.0f / 6};
  expect_near(values(resize_bilinear(ramp(), 1, 3, false, true)), want, 1e-4f);
  expect_near(values(resize_bilinear_reference(ramp(), 1, 3, false, true)), want, 1e-4f);
}

TEST(ResizeBilinear, HalfPixelCentersTwoDimensions) {
  // 2×2 -> 3×3: rows/cols sample at -1/6 (clamped to 0), 1/2 and 7/6 (clamped to 1).
  const Tensor x = torch::tensor({0.0f, 10.0f, 20.0f, 30.0f}).reshape({1, 2, 2, 1});
  const std::vector<float> want = {0, 5, 10, 10, 15, 20, 20, 25, 30};
  expect_near(values(resize_bilinear(x, 3, 3, false, true)), want);
  expect_near(values(resize_bilinear_reference(x, 3, 3, false, true)), want);
}

TEST(ResizeBilinear, AlignCorners) {
  // src = dst * 3/7: value = 30 * dst / 7.
  std::vector<float> want;
  for (int i = 0; i < 8; ++i) want.push_back(30.0f * i / 7);
  expect_near(values(resize_bilinear(ramp(), 1, 8, true, false)), want, 1e-4f);
  expect_near(values(resize_bilinear_reference(ramp(), 1, 8, true, false)), want, 1e-4f);
}

TEST(ResizeBilinear, LegacyModeSamplesAtDstTimesScale) {
  // src = dst * 0.5; the last sample (3.5) takes the edge value.
  const std::vector<float> want = {0, 5, 10, 15, 20, 25, 30, 30};
  expect_near(values(resize_bilinear(ramp(), 1, 8, false, false)), want);
}

TEST(ResizeBilinear, TorchPathEqualsTfKernelOnRandomSizes) {
  torch::manual_seed(3);
  const Tensor x = torch::randn({1, 7, 10, 3});
  for (const auto& [oh, ow] : std::vector<std::pair<int, int>>{
           {14, 20}, {28, 40}, {5, 4}, {3, 17}, {7, 10}, {1, 1}, {13, 9}}) {
    for (const bool align : {false, true}) {
      const Tensor fast = resize_bilinear(x, oh, ow, align, !align);
      const Tensor ref = resize_bilinear_reference(x, oh, ow, align, !align);
      ASSERT_EQ(shape(fast), shape(ref));
      EXPECT_LT((fast - ref).abs().max().item<float>(), 1e-5f)
          << oh << "x" << ow << (align ? " align_corners" : " half_pixel_centers");
    }
  }
}

TEST(ResizeBilinear, IntegerInputGivesFloat) {
  const Tensor y = resize_bilinear(ramp().to(torch::kInt), 1, 8, false, true);
  EXPECT_EQ(y.scalar_type(), torch::kFloat);
  EXPECT_FLOAT_EQ(values(y)[1], 2.5f);
}

// x = arange(24) as 2×3×4.
Tensor cube() { return torch::arange(24, torch::kInt).reshape({2, 3, 4}); }

TEST(StridedSlice, BeginEndMasks) {
  SliceMasks m;
  m.begin = m.end = 1;  // x[:, 1:3]
  const Tensor y = strided_slice(cube(), {0, 1}, {0, 3}, {1, 1}, m);
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{2, 2, 4}));
  EXPECT_EQ(ivalues(y)[0], 4);
  EXPECT_EQ(ivalues(y)[8], 16);
}

TEST(StridedSlice, ShrinkAxis) {
  SliceMasks m;
  m.shrink_axis = 1;  // x[1]
  const Tensor y = strided_slice(cube(), {1}, {2}, {1}, m);
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{3, 4}));
  EXPECT_EQ(ivalues(y)[0], 12);
  m.shrink_axis = 1;  // x[-1] is x[1]
  EXPECT_TRUE(torch::equal(strided_slice(cube(), {-1}, {0}, {1}, m), y));
  EXPECT_THROW(strided_slice(cube(), {2}, {3}, {1}, m), OpError);  // out of bounds
}

TEST(StridedSlice, EllipsisWithShrink) {
  SliceMasks m;
  m.ellipsis = 1;
  m.shrink_axis = 2;  // x[..., 2]
  const Tensor y = strided_slice(cube(), {0, 2}, {0, 3}, {1, 1}, m);
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(ivalues(y), (std::vector<std::int64_t>{2, 6, 10, 14, 18, 22}));
}

TEST(StridedSlice, NewAxis) {
  SliceMasks m;
  m.begin = m.end = 1;
  m.new_axis = 2;  // x[:, None]
  EXPECT_EQ(shape(strided_slice(cube(), {0, 0}, {0, 0}, {1, 1}, m)),
            (std::vector<std::int64_t>{2, 1, 3, 4}));
  // The models' pattern: begin_mask 3, end_mask 3, new_axis 4 on a rank-2 tensor: x[:, :, None].
  SliceMasks n;
  n.begin = n.end = 3;
  n.new_axis = 4;
  const Tensor x2 = torch::arange(6, torch::kInt).reshape({2, 3});
  const Tensor y = strided_slice(x2, {0, 0, 0}, {0, 0, 0}, {1, 1, 1}, n);
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{2, 3, 1}));
  EXPECT_EQ(ivalues(y), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  // Ellipsis then a new axis at the end: x[..., None] keeps every dimension.
  SliceMasks e;
  e.ellipsis = 1;
  e.new_axis = 2;
  EXPECT_EQ(shape(strided_slice(cube(), {0, 0}, {0, 0}, {1, 1}, e)),
            (std::vector<std::int64_t>{2, 3, 4, 1}));
}

TEST(StridedSlice, NegativeStridesAndIndices) {
  SliceMasks m;
  m.begin = m.end = 7;  // x[:, :, ::-1]
  const Tensor y = strided_slice(cube(), {0, 0, 0}, {0, 0, 0}, {1, 1, -1}, m);
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{2, 3, 4}));
  const std::vector<std::int64_t> yv = ivalues(y);
  EXPECT_EQ(std::vector<std::int64_t>(yv.begin(), yv.begin() + 4),
            (std::vector<std::int64_t>{3, 2, 1, 0}));
  // An unmasked begin 0 with stride -1 and the end masked: x[:, :, 0::-1], one element.
  SliceMasks z0;
  z0.begin = 3;
  z0.end = 7;
  EXPECT_EQ(shape(strided_slice(cube(), {0, 0, 0}, {0, 0, 0}, {1, 1, -1}, z0)),
            (std::vector<std::int64_t>{2, 3, 1}));
  SliceMasks k;
  k.begin = k.end = 3;  // x[:, :, -3:-1]
  const Tensor z = strided_slice(cube(), {0, 0, -3}, {0, 0, -1}, {1, 1, 1}, k);
  EXPECT_EQ(shape(z), (std::vector<std::int64_t>{2, 3, 2}));
  EXPECT_EQ(ivalues(z)[0], 1);
  EXPECT_EQ(ivalues(z)[1], 2);
  // x1[3:0:-2] = {3, 1}; x1[1:100:2] = {1, 3} (end clamped).
  const Tensor x1 = torch::arange(5, torch::kInt);
  EXPECT_EQ(ivalues(strided_slice(x1, {3}, {0}, {-2}, {})), (std::vector<std::int64_t>{3, 1}));
  EXPECT_EQ(ivalues(strided_slice(x1, {1}, {100}, {2}, {})), (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ(shape(strided_slice(x1, {3}, {1}, {1}, {})), (std::vector<std::int64_t>{0}));
}

TEST(FloorDiv, IntegersRoundTowardNegativeInfinity) {
  const Tensor x = torch::tensor({-7, 7, -7, 7, -6, 0, -1}, torch::kInt);
  const Tensor y = torch::tensor({2, 2, -2, -2, 3, 5, 4}, torch::kInt);
  const Tensor q = floor_div(x, y);
  EXPECT_EQ(q.scalar_type(), torch::kInt);
  EXPECT_EQ(ivalues(q), (std::vector<std::int64_t>{-4, 3, 3, -4, -2, 0, -1}));
}

TEST(FloorDiv, FloatsAreFloorOfQuotient) {
  const Tensor q =
      floor_div(torch::tensor({-7.5f, 7.5f, 6.0f}), torch::tensor({2.0f, -2.0f, 3.0f}));
  expect_near(values(q), {-4, -4, 2});
}

TEST(Cast, FloatToIntTruncatesTowardZero) {
  const Tensor x = torch::tensor({-2.7f, 2.7f, -0.5f, 3.0f});
  EXPECT_EQ(ivalues(cast(x, torch::kInt)), (std::vector<std::int64_t>{-2, 2, 0, 3}));
  EXPECT_EQ(ivalues(cast(torch::tensor({0.0f, -0.1f}), torch::kBool).to(torch::kInt)),
            (std::vector<std::int64_t>{0, 1}));
}

TEST(TopK, TiesGoToTheLowerIndexFirst) {
  const auto [v, i] = top_k(torch::tensor({1.0f, 3.0f, 3.0f, 2.0f, 3.0f, 0.0f}), 4);
  expect_near(values(v), {3, 3, 3, 2});
  EXPECT_EQ(i.scalar_type(), torch::kInt);
  EXPECT_EQ(ivalues(i), (std::vector<std::int64_t>{1, 2, 4, 3}));
  // Many ties in a long row (where sort algorithms switch strategy).
  const Tensor big = torch::arange(5000, torch::kInt).remainder(7).to(torch::kFloat);
  const auto [bv, bi] = top_k(big.unsqueeze(0), 20);
  std::vector<std::int64_t> want;
  for (int k = 0; k < 20; ++k) want.push_back(6 + 7 * k);
  EXPECT_EQ(ivalues(bi), want);
  EXPECT_THROW(top_k(big, 5001), OpError);
}

TEST(ArgMax, FirstMaximumOnTies) {
  EXPECT_EQ(ivalues(arg_max(torch::tensor({1.0f, 5.0f, 5.0f, 2.0f}), 0)),
            (std::vector<std::int64_t>{1}));
  const Tensor x = torch::tensor({2.0f, 2.0f, 1.0f, 0.0f, 4.0f, 4.0f}).reshape({2, 3});
  EXPECT_EQ(ivalues(arg_max(x, -1)), (std::vector<std::int64_t>{0, 1}));
  EXPECT_EQ(ivalues(arg_max(torch::zeros({1000}), 0)), (std::vector<std::int64_t>{0}));
}

TEST(GatherNd, IndexesLeadingDimensions) {
  const Tensor params = torch::arange(12, torch::kFloat).reshape({2, 3, 2});
  // M = 2: rows of the last dimension.
  const Tensor y = gather_nd(params, torch::tensor({1, 2, 0, 1}, torch::kInt).reshape({2, 2}));
  EXPECT_EQ(shape(y), (std::vector<std::int64_t>{2, 2}));
  expect_near(values(y), {10, 11, 2, 3});
  // M = 3: scalars, batch shape kept.
  const Tensor z =
      gather_nd(params, torch::tensor({1, 2, 1, 0, 0, 1}, torch::kInt).reshape({1, 2, 3}));
  EXPECT_EQ(shape(z), (std::vector<std::int64_t>{1, 2}));
  expect_near(values(z), {11, 1});
  // M = 1: whole slices.
  const Tensor s = gather_nd(params, torch::tensor({1}, torch::kInt).reshape({1, 1}));
  EXPECT_EQ(shape(s), (std::vector<std::int64_t>{1, 3, 2}));
  EXPECT_EQ(values(s)[0], 6);
  EXPECT_THROW(gather_nd(params, torch::tensor({2, 0}, torch::kInt).reshape({1, 2})), OpError);
  EXPECT_THROW(gather_nd(params, torch::tensor({0, -1}, torch::kInt).reshape({1, 2})), OpError);
}

TEST(GatherNd, IsDifferentiable) {
  const Tensor params = torch::arange(6, torch::kFloat).reshape({2, 3}).requires_grad_();
  const Tensor y =
      gather_nd(params, torch::tensor({1, 2, 1, 2, 0, 0}, torch::kInt).reshape({3, 2}));
  y.sum().backward();
  expect_near(values(params.grad()), {1, 0, 0, 0, 0, 2});
}

TEST(Range, FloatAccumulatesAndIntCountsExactly) {
  expect_near(values(range(torch::scalar_tensor(0.0f), torch::scalar_tensor(4.0f),
                           torch::scalar_tensor(1.0f))),
              {0, 1, 2, 3});
  const Tensor r =
      range(torch::scalar_tensor(1, torch::kInt), torch::scalar_tensor(-6, torch::kInt),
            torch::scalar_tensor(-3, torch::kInt));
  EXPECT_EQ(r.scalar_type(), torch::kInt);
  EXPECT_EQ(ivalues(r), (std::vector<std::int64_t>{1, -2, -5}));
  // 0, 0.1, ... accumulated in float: 10 values (ceil(1 / 0.1f)), the last one 0.1f added 9 times.
  const Tensor f =
      range(torch::scalar_tensor(0.0f), torch::scalar_tensor(1.0f), torch::scalar_tensor(0.1f));
  ASSERT_EQ(f.numel(), 10);
  float acc = 0;
  for (int i = 0; i < 9; ++i) acc += 0.1f;
  EXPECT_EQ(values(f)[9], acc);
  EXPECT_THROW(range(torch::scalar_tensor(5, torch::kInt), torch::scalar_tensor(1, torch::kInt),
                     torch::scalar_tensor(1, torch::kInt)),
               OpError);
}

TEST(Squeeze, ListedOrAllUnitDimensions) {
  const Tensor x = torch::zeros({1, 3, 1, 2});
  EXPECT_EQ(shape(squeeze_dims(x, {})), (std::vector<std::int64_t>{3, 2}));
  EXPECT_EQ(shape(squeeze_dims(x, {-2})), (std::vector<std::int64_t>{1, 3, 2}));
  EXPECT_THROW(squeeze_dims(x, {1}), OpError);
}

TEST(Select, VectorConditionPicksRows) {
  const Tensor t = torch::ones({3, 2});
  const Tensor e = torch::zeros({3, 2});
  const Tensor y = select_v1(torch::tensor({true, false, true}), t, e);
  expect_near(values(y), {1, 1, 0, 0, 1, 1});
}

TEST(Reduce, KeepsIntegerDtypeAndHandlesNegativeAxes) {
  const Tensor x = torch::arange(6, torch::kInt).reshape({2, 3});
  const Tensor s = reduce(x, {-1}, Reduction::kSum, false);
  EXPECT_EQ(s.scalar_type(), torch::kInt);
  EXPECT_EQ(ivalues(s), (std::vector<std::int64_t>{3, 12}));
  EXPECT_EQ(shape(reduce(x.to(torch::kFloat), {0, 1, 1}, Reduction::kMax, true)),
            (std::vector<std::int64_t>{1, 1}));
  EXPECT_TRUE(torch::equal(reduce(x, {}, Reduction::kSum, false), x));
}

}  // namespace
}  // namespace wheelpose::learn::ops

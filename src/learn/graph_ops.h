#pragma once
// TensorFlow op semantics on LibTorch tensors, for GraphModule (internal to the learn layer:
// includes torch). Tensors are in TF's logical layout (NHWC images); every op here is
// differentiable where TF's is. Bad arguments found at run time throw OpError, which
// GraphModule re-throws as an Error naming the node.

#include <torch/torch.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace wheelpose::learn::ops {

struct OpError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Padding {
  enum class Kind { kSame, kValid, kExplicit };
  Kind kind = Kind::kValid;
  std::int64_t top = 0, bottom = 0, left = 0, right = 0;  // kExplicit
};

// TF's SAME padding of one dimension: {before, after}, after >= before.
std::pair<std::int64_t, std::int64_t> same_padding(std::int64_t in, std::int64_t kernel,
                                                   std::int64_t stride, std::int64_t dilation);

enum class Activation { kNone, kRelu, kRelu6, kElu, kLeakyRelu, kSigmoid, kTanh, kPrelu };

struct ConvSpec {
  bool depthwise = false;
  std::array<std::int64_t, 2> stride{1, 1};    // h, w
  std::array<std::int64_t, 2> dilation{1, 1};  // h, w
  Padding padding;
  bool bias = false;
  Activation activation = Activation::kNone;
  double alpha = 0.2;                   // LeakyRelu
  bool filter_in_torch_layout = false;  // else TF's [kh, kw, in, out|mult]
};

// TF depthwise filter [kh, kw, in, mult] to torch's grouped layout [in*mult, 1, kh, kw]
// (output channel c*mult + m, as TF orders them).
torch::Tensor depthwise_filter_to_torch(const torch::Tensor& filter);

// Conv2D / DepthwiseConv2dNative (+ fused bias and activation) on an NHWC tensor; returns NHWC.
// `bias` and `prelu_alpha` may be undefined. Runs on an NCHW view, channels-last in memory if
// `channels_last`, else NCHW-contiguous.
torch::Tensor conv2d_nhwc(const torch::Tensor& x, const torch::Tensor& filter,
                          const torch::Tensor& bias, const torch::Tensor& prelu_alpha,
                          const ConvSpec& spec, bool channels_last);

// MaxPool on NHWC; padding never wins the max (TF excludes it).
torch::Tensor max_pool_nhwc(const torch::Tensor& x, std::array<std::int64_t, 2> ksize,
                            std::array<std::int64_t, 2> stride, const Padding& padding,
                            bool channels_last);

// ResizeBilinear with TF's exact sampling. half_pixel_centers: src = (dst + 0.5) * in/out - 0.5;
// align_corners: src = dst * (in - 1)/(out - 1); neither (legacy): src = dst * in/out; then
// lower = max(floor(src), 0), upper = min(ceil(src), in - 1), weight src - floor(src). The
// first two run on torch's upsample_bilinear2d (the same sampling), legacy on
// resize_bilinear_reference. Returns float NHWC.
torch::Tensor resize_bilinear(const torch::Tensor& x, std::int64_t out_h, std::int64_t out_w,
                              bool align_corners, bool half_pixel_centers);
// The same computed by index_select and lerps, following TF's kernel line by line.
torch::Tensor resize_bilinear_reference(const torch::Tensor& x, std::int64_t out_h,
                                        std::int64_t out_w, bool align_corners,
                                        bool half_pixel_centers);

// Cast: float to integer truncates toward zero; to bool is x != 0.
torch::Tensor cast(const torch::Tensor& x, torch::ScalarType dtype);

// FloorDiv: floor(x / y) for floats; mathematical floor division for integers (-7 / 2 = -4).
torch::Tensor floor_div(const torch::Tensor& x, const torch::Tensor& y);

// Select (v1): `cond` has the shape of `t`, or is a vector over t's first dimension, or a scalar.
torch::Tensor select_v1(const torch::Tensor& cond, const torch::Tensor& t, const torch::Tensor& e);

enum class Reduction { kSum, kMax, kMin, kMean };
// Sum/Max/Min/Mean over `axes` (negative allowed, repeats ignored); keeps the dtype.
torch::Tensor reduce(const torch::Tensor& x, std::vector<std::int64_t> axes, Reduction r,
                     bool keep_dims);

// ArgMax along `dim` (negative allowed): the first index of the maximum. int64.
torch::Tensor arg_max(const torch::Tensor& x, std::int64_t dim);

// TopKV2 along the last dimension: the k largest, descending; ties by lower index first.
// Returns {values, int32 indices}.
std::pair<torch::Tensor, torch::Tensor> top_k(const torch::Tensor& x, std::int64_t k);

// GatherNd: indices[..., M] index the first M dimensions of params; out-of-range indices throw.
torch::Tensor gather_nd(const torch::Tensor& params, const torch::Tensor& indices);

// Squeeze `dims` (all size-1 dimensions if empty); a listed dimension of size != 1 throws.
torch::Tensor squeeze_dims(const torch::Tensor& x, const std::vector<std::int64_t>& dims);

struct SliceMasks {
  std::int64_t begin = 0, end = 0, ellipsis = 0, new_axis = 0, shrink_axis = 0;
};
// StridedSlice with TF's full mask semantics (tensorflow/core/util/strided_slice_op.cc).
torch::Tensor strided_slice(const torch::Tensor& x, const std::vector<std::int64_t>& begin,
                            const std::vector<std::int64_t>& end,
                            const std::vector<std::int64_t>& strides, const SliceMasks& masks);

// Range(start, limit, delta) of the inputs' dtype; float values accumulate (v += delta) as TF's
// and TF.js's kernels do.
torch::Tensor range(const torch::Tensor& start, const torch::Tensor& limit,
                    const torch::Tensor& delta);

// An integer tensor's values (any shape, row-major) / its single value.
std::vector<std::int64_t> int_values(const torch::Tensor& t);
std::int64_t int_value(const torch::Tensor& t);

}  // namespace wheelpose::learn::ops

// Buffers and command sequences: transfers, automatic barriers between dependent dispatches, re-submission and
// per-command timestamps.
#include <gtest/gtest.h>

#include "common/gpu.hpp"
#include "common/test_support.hpp"
#include "kernel_test_util.hpp"
#include "runtime/context.hpp"
#include "runtime/host_transfer.hpp"
#include "runtime/ops.hpp"

namespace vkvo::rt {
namespace {

using test::gpu;

TEST(Buffer, RoundTripsBytesAtOffsets) {
  Buffer buffer(gpu(), 1000, BufferKind::device, "roundtrip");
  std::vector<std::uint8_t> data(300);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7);
  buffer.upload(data.data(), data.size(), 500);
  std::vector<std::uint8_t> back(300);
  buffer.download(back.data(), back.size(), 500);
  EXPECT_EQ(back, data);
}

// The discrete-GPU path on any device: shaders' buffers unmapped, every transfer through staging, the staging
// buffer kept from the second transfer on, and a sequence's results the same as with mapped buffers.
TEST(Buffer, DiscreteMemoryTransfersThroughAKeptStagingBuffer) {
  const Context discrete({.pipeline_cache = false, .use_unified_memory = false});
  EXPECT_FALSE(discrete.caps().unified_memory);
  Buffer buffer(discrete, 1000, BufferKind::device, "discrete");
  EXPECT_FALSE(buffer.host_visible());
  std::vector<std::uint8_t> data(300);
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint8_t>(i * 7 + 1);
  buffer.upload(data.data(), data.size(), 500);
  EXPECT_FALSE(buffer.keeps_staging()) << "a single transfer (a weight upload) keeps nothing";
  std::vector<std::uint8_t> back(300);
  buffer.download(back.data(), back.size(), 500);
  EXPECT_EQ(back, data);
  EXPECT_TRUE(buffer.keeps_staging());
  // The kept staging buffer serves transfers of any range; the bytes outside it are untouched.
  const std::vector<std::uint8_t> head{9, 8, 7, 6};
  buffer.upload(std::span<const std::uint8_t>(head));
  EXPECT_EQ(buffer.download<std::uint8_t>(4), head);
  EXPECT_EQ(buffer.download<std::uint8_t>(300, 500), data);
  buffer.fill_zero();
  EXPECT_EQ(buffer.download<std::uint8_t>(1000), std::vector<std::uint8_t>(1000, 0));

  // A GEMM through the staging path gives what it gives with mapped buffers.
  const std::uint32_t n = 17;
  const auto a = test::random_values(n * n, 1), b = test::random_values(n * n, 2);
  auto product = [&](const Context& ctx) {
    Buffer da(ctx, a.size() * 4), db(ctx, b.size() * 4), dc(ctx, a.size() * 4);
    da.upload(std::span<const float>(a));
    db.upload(std::span<const float>(b));
    Gemm gemm(ctx, Precision::fp32);
    Sequence seq(ctx);
    seq.begin();
    gemm.record(seq, da, db, nullptr, dc, {.m = n, .n = n, .k = n});
    seq.end();
    seq.submit();
    return dc.download<float>(a.size());
  };
  EXPECT_EQ(product(discrete), product(gpu()));
}

// A call's input and output as part of its sequence: through staging copies where the device buffers are not
// mapped, in place where they are; either way one submission per call, each call seeing that call's input.
TEST(HostTransfer, InputsAndOutputsRideInTheSequence) {
  const Context discrete({.pipeline_cache = false, .use_unified_memory = false});
  for (const Context* context : {&static_cast<const Context&>(gpu()), &discrete}) {
    SCOPED_TRACE(context == &discrete ? "staged" : "mapped");
    Buffer in_buf(*context, 64 * sizeof(float), BufferKind::device, "in");
    Buffer out_buf(*context, 64 * sizeof(float), BufferKind::device, "out");
    const HostInput input(*context, in_buf);
    const HostOutput output(*context, out_buf);
    EXPECT_EQ(input.staged(), context == &discrete);
    EXPECT_EQ(output.staged(), context == &discrete);
    Sequence seq(*context, 0);
    seq.begin();
    input.record(seq);
    seq.copy(in_buf, out_buf, in_buf.size());  // stands in for the kernels between them
    output.record(seq);
    seq.end();
    for (float call : {1.0f, 2.0f, 3.0f}) {
      std::vector<float> values(64);
      for (std::size_t i = 0; i < values.size(); ++i) values[i] = call * 100 + float(i);
      input.write(values.data(), values.size() * sizeof(float));
      const std::uint64_t before = context->submission_count();
      seq.submit();
      EXPECT_EQ(output.read<float>(64), values) << "call " << call;
      EXPECT_EQ(context->submission_count() - before, 1u) << "call " << call;
    }
  }
}

TEST(Buffer, OverrunIsAnErrorNamingTheBuffer) {
  Buffer buffer(gpu(), 64, BufferKind::device, "small_buffer");
  std::vector<std::uint8_t> data(65);
  try {
    buffer.upload(data.data(), data.size());
    FAIL() << "expected VulkanError";
  } catch (const VulkanError& e) {
    EXPECT_NE(std::string(e.what()).find("small_buffer"), std::string::npos) << e.what();
  }
}

TEST(Buffer, ZeroSizedBufferIsValid) {
  Buffer empty(gpu(), 0);
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_NO_THROW(empty.upload(nullptr, 0));
}

// A chain where every GEMM reads the previous result: wrong or missing barriers give wrong numbers.
TEST(Sequence, DependentDispatchesSeeEachOthersResultsAndResubmitRepeats) {
  auto& ctx = gpu();
  const std::uint32_t n = 33;
  std::vector<float> identity_x2(n * n, 0.0f);
  for (std::uint32_t i = 0; i < n; ++i) identity_x2[i * n + i] = 2.0f;
  const auto x = test::random_values(n * n, 5);
  Buffer staging(ctx, x.size() * 4, BufferKind::staging, "input");
  staging.upload(std::span<const float>(x));
  Buffer ping(ctx, x.size() * 4, BufferKind::device, "ping"), pong(ctx, x.size() * 4, BufferKind::device, "pong");
  Buffer scale(ctx, identity_x2.size() * 4, BufferKind::device, "2I");
  scale.upload(std::span<const float>(identity_x2));

  const Gemm gemm(ctx, Precision::fp32);
  const GemmShape shape{.m = n, .n = n, .k = n};
  // Timestamps after the first 512 commands (the default), and after none: the same results, no timings.
  Sequence seq(ctx), untimed(ctx, 0);
  for (Sequence* s : {&untimed, &seq}) {
    s->begin();
    s->copy(staging, ping, x.size() * 4);
    for (int i = 0; i < 3; ++i) {  // ping -> pong -> ping -> pong, each step x2
      gemm.record(*s, i % 2 ? pong : ping, scale, nullptr, i % 2 ? ping : pong, shape);
    }
    s->end();
    for (int run = 0; run < 2; ++run) {
      s->submit();
      const auto y = pong.download<float>(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) ASSERT_NEAR(y[i], 8.0f * x[i], 1e-5f) << "run " << run << " at " << i;
    }
    EXPECT_EQ(s->command_count(), 4u);
  }
  EXPECT_TRUE(untimed.timings().empty());
  EXPECT_EQ(untimed.gpu_ms(), 0.0);
  if (ctx.caps().timestamps) {
    const auto timings = seq.timings();
    ASSERT_EQ(timings.size(), 4u);
    EXPECT_EQ(timings[0].label, "copy");
    for (const auto& t : timings) EXPECT_GE(t.ms, 0.0) << t.label;
    EXPECT_GT(seq.gpu_ms(), 0.0);
  }
}

TEST(Sequence, WrongBindingCountIsRejected) {
  auto& ctx = gpu();
  const Kernel kernel(ctx, {.op = Op::maxpool2x2, .precision = Precision::fp32});
  Buffer a(ctx, 64);
  Sequence seq(ctx);
  seq.begin();
  const std::uint32_t push[5] = {};
  EXPECT_THROW(seq.dispatch(kernel, {a}, push, Groups{1}), VulkanError);
  seq.end();
}

TEST(Sequence, WrongPushConstantSizeIsRejected) {
  auto& ctx = gpu();
  const Kernel kernel(ctx, {.op = Op::maxpool2x2, .precision = Precision::fp32});
  Buffer a(ctx, 64), b(ctx, 64);
  Sequence seq(ctx);
  seq.begin();
  const std::uint32_t push[4] = {};  // MaxPoolPush has 5 members
  const std::string error = test::error_of([&] { seq.dispatch(kernel, {a, b}, push, Groups{1}); });
  EXPECT_NE(error.find("kernel 'maxpool2x2' takes 20 push-constant bytes, 16 given"), std::string::npos) << error;
  seq.end();
}

}  // namespace
}  // namespace vkvo::rt

// Framed, checksummed messages over a byte link (the emulated UART between the firmware and `lashid hil`, or any
// serial line). Header-only, heap-free, no exceptions; the firmware and the host tool share this file.
//
// Frame:  0xA5 0x5A | type | seq | len | payload[len] | crc16 (lo, hi)
//   crc16 = CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection) over type, seq, len and the payload.
//   Multi-byte payload fields are little-endian; floats are IEEE-754 binary32.
// A frame whose checksum or length is wrong is dropped and counted, never delivered: the decoder resynchronises
// on the next 0xA5 0x5A. Lost frames are detected by the sample exchange (t must match, see RemotePlantPort).
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace lashid::hal::link {

inline constexpr std::uint8_t kSync0 = 0xA5;
inline constexpr std::uint8_t kSync1 = 0x5A;
inline constexpr std::size_t kMaxPayload = 128;
inline constexpr std::size_t kOverhead = 7;  // 2 sync + type + seq + len + 2 crc
inline constexpr std::size_t kMaxFrame = kMaxPayload + kOverhead;
/// The payload of the plant port's frames (kActuate, kMeasurement: u32 t, f32 value); an empty kMeasurement ends a
/// session.
inline constexpr std::size_t kExchangePayload = 8;

enum class MessageType : std::uint8_t {
  kActuate = 0x01,      ///< firmware -> host: u32 t, f32 v. "Apply v at sample t and measure."
  kMeasurement = 0x02,  ///< host -> firmware: u32 t, f32 y. The answer to kActuate with the same t.
  kCommand = 0x10,      ///< host -> firmware: u8 Command
  kStatus = 0x11,       ///< firmware -> host: u8 stage, u32 samples done, u32 link errors
  kDesign = 0x12,       ///< host -> firmware: the run's design (firmware/run_design.hpp), before kStart
  kDesignStatus = 0x13, ///< firmware -> host: u8 DesignStatus, the answer to kDesign (0 = accepted)
  kEstimate = 0x20,     ///< firmware -> host: one scheme's estimate (EstimateRecord)
  kCrossCheck = 0x21,   ///< firmware -> host: Remark 3b cross-check (CrossCheckRecord)
  kCost = 0x22,         ///< firmware -> host: footprint and cost (CostRecord)
  /// firmware -> host, with kStartStreamSamples: consecutive samples of the run as the board measured them
  /// (SampleBlock: u32 first index, u8 count, u16 set-aside bits, count x (f32 v, f32 y)), for the recording of a
  /// plant the host does not play.
  kSamples = 0x23,
  kLog = 0x30,          ///< firmware -> host: text
  kDone = 0x3F,         ///< firmware -> host: u8 overall status (0 = ok); the run is over
};

/// The payload of kCommand: the command byte, then the command's arguments.
///   kStart [flags]  start the run of the design received (kStartHoldReports, kStartStreamSamples: see below)
///   kStop           end the run now (its reports are sent)
///   kQuery          answered with a kStatus
///   kReport         after the run: send every report again (estimates, cross-check, cost, done); a host that lost
///                   one on the link asks for them again. Answered only while the firmware holds its reports.
///   kFinish         the host has every report: the firmware stops holding them and the run ends
/// A command frame whose first byte is not a command, or with arguments a command does not take, is ignored.
enum class Command : std::uint8_t { kStart = 1, kStop = 2, kQuery = 3, kReport = 4, kFinish = 5 };

/// kStart flag: after the reports, hold them (answer kReport) until kFinish or the board's hold time, so that a
/// report lost on the link can be asked for again. Without it the run ends as soon as the reports are sent.
inline constexpr std::uint8_t kStartHoldReports = 0x01;
/// kStart flag: send every sample of the run as measured (kSamples frames), on a board whose link writes do not wait
/// for the wire (hal::BuffersLinkWrites); other boards ignore it. The host records a plant it does not play so.
inline constexpr std::uint8_t kStartStreamSamples = 0x02;

/// CRC-16/CCITT-FALSE, bitwise (small code; a table would cost 512 bytes of flash for no measurable gain here).
/// The arithmetic is in `unsigned` (no signed promotions): bits above 15 only ever move left, never into the low
/// 16, so masking once at the end is exact.
constexpr std::uint16_t crc16(std::uint16_t crc, std::uint8_t byte) {
  unsigned c = static_cast<unsigned>(crc) ^ (static_cast<unsigned>(byte) << 8U);
  for (int bit = 0; bit < 8; ++bit) c = (c & 0x8000U) != 0U ? (c << 1U) ^ 0x1021U : c << 1U;
  return static_cast<std::uint16_t>(c & 0xFFFFU);
}
static_assert(crc16(crc16(crc16(crc16(crc16(crc16(crc16(crc16(crc16(0xFFFF, '1'), '2'), '3'), '4'), '5'), '6'), '7'),
                                '8'),
                          '9') == 0x29B1,
              "CRC-16/CCITT-FALSE check value");

/// Little-endian payload writer over a fixed buffer; overflow sets ok() false instead of writing past the end.
class PayloadWriter {
 public:
  void u8(std::uint8_t x) { put(x); }
  void u16(std::uint16_t x) {
    put(static_cast<std::uint8_t>(x));
    put(static_cast<std::uint8_t>(x >> 8));
  }
  void u32(std::uint32_t x) {
    for (int shift = 0; shift < 32; shift += 8) put(static_cast<std::uint8_t>(x >> shift));
  }
  void u64(std::uint64_t x) {
    u32(static_cast<std::uint32_t>(x));
    u32(static_cast<std::uint32_t>(x >> 32));
  }
  void f32(float x) { u32(std::bit_cast<std::uint32_t>(x)); }
  bool ok() const { return ok_; }
  std::size_t size() const { return size_; }
  const std::uint8_t* data() const { return bytes_.data(); }

 private:
  void put(std::uint8_t x) {
    if (size_ >= kMaxPayload) {
      ok_ = false;
      return;
    }
    bytes_[size_++] = x;
  }
  std::array<std::uint8_t, kMaxPayload> bytes_{};
  std::size_t size_ = 0;
  bool ok_ = true;
};

/// Little-endian payload reader; reading past the end sets ok() false and yields zeros.
class PayloadReader {
 public:
  PayloadReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t u8() { return get(); }
  std::uint16_t u16() {
    const unsigned lo = get();
    return static_cast<std::uint16_t>(lo | (static_cast<unsigned>(get()) << 8U));
  }
  std::uint32_t u32() {
    std::uint32_t x = 0;
    for (int shift = 0; shift < 32; shift += 8) x |= static_cast<std::uint32_t>(get()) << shift;
    return x;
  }
  std::uint64_t u64() {
    const std::uint64_t lo = u32();
    return lo | (static_cast<std::uint64_t>(u32()) << 32);
  }
  float f32() { return std::bit_cast<float>(u32()); }
  bool ok() const { return ok_; }
  bool at_end() const { return pos_ == size_; }

 private:
  std::uint8_t get() {
    if (pos_ >= size_) {
      ok_ = false;
      return 0;
    }
    return data_[pos_++];
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

/// Serialises one frame into `out` (at least kOverhead + payload size bytes); returns the frame length, 0 if the
/// payload is too long.
inline std::size_t encode_frame(MessageType type, std::uint8_t seq, const std::uint8_t* payload,
                                std::size_t payload_size, std::uint8_t* out) {
  if (payload_size > kMaxPayload) return 0;
  out[0] = kSync0;
  out[1] = kSync1;
  out[2] = static_cast<std::uint8_t>(type);
  out[3] = seq;
  out[4] = static_cast<std::uint8_t>(payload_size);
  std::uint16_t crc = 0xFFFF;
  for (std::size_t i = 2; i < 5; ++i) crc = crc16(crc, out[i]);
  for (std::size_t i = 0; i < payload_size; ++i) {
    out[5 + i] = payload[i];
    crc = crc16(crc, payload[i]);
  }
  out[5 + payload_size] = static_cast<std::uint8_t>(crc);
  out[6 + payload_size] = static_cast<std::uint8_t>(crc >> 8);
  return payload_size + kOverhead;
}

struct Frame {
  MessageType type = MessageType::kLog;
  std::uint8_t seq = 0;
  std::uint8_t size = 0;
  std::array<std::uint8_t, kMaxPayload> payload{};
  PayloadReader reader() const { return PayloadReader(payload.data(), size); }
};

/// Byte-by-byte frame decoder with error counters.
class FrameDecoder {
 public:
  enum class Result : std::uint8_t { kNeedMore, kFrame, kDropped };

  /// `max_payload`: the longest payload this link carries. A length byte beyond it is a damaged frame at once, so a
  /// garbled length cannot make the decoder swallow the frames that follow (the plant port: kExchangePayload).
  constexpr explicit FrameDecoder(std::size_t max_payload = kMaxPayload)
      : max_payload_(max_payload < kMaxPayload ? max_payload : kMaxPayload) {}

  /// Feeds one byte. kFrame: frame() holds a complete, checksum-verified frame. kDropped: a damaged frame was
  /// discarded (counted in crc_errors() or length_errors()).
  Result push(std::uint8_t byte) {
    switch (state_) {
      case State::kHunt0:
        if (byte == kSync0) state_ = State::kHunt1;
        return Result::kNeedMore;
      case State::kHunt1:
        state_ = byte == kSync1 ? State::kType : (byte == kSync0 ? State::kHunt1 : State::kHunt0);
        return Result::kNeedMore;
      case State::kType:
        frame_.type = static_cast<MessageType>(byte);
        crc_ = crc16(0xFFFF, byte);
        state_ = State::kSeq;
        return Result::kNeedMore;
      case State::kSeq:
        frame_.seq = byte;
        crc_ = crc16(crc_, byte);
        state_ = State::kLength;
        return Result::kNeedMore;
      case State::kLength:
        if (byte > max_payload_) {
          ++length_errors_;
          // A frame cut short after its header puts the next frame's first sync byte (0xA5, never a valid length
          // of the link's payloads) here: it is kept as the start of that frame, which is then not lost as well.
          state_ = byte == kSync0 ? State::kHunt1 : State::kHunt0;
          return Result::kDropped;
        }
        frame_.size = byte;
        crc_ = crc16(crc_, byte);
        received_ = 0;
        state_ = byte == 0 ? State::kCrcLo : State::kPayload;
        return Result::kNeedMore;
      case State::kPayload:
        frame_.payload[received_++] = byte;
        crc_ = crc16(crc_, byte);
        if (received_ == frame_.size) state_ = State::kCrcLo;
        return Result::kNeedMore;
      case State::kCrcLo:
        crc_lo_ = byte;
        state_ = State::kCrcHi;
        return Result::kNeedMore;
      case State::kCrcHi:
        state_ = State::kHunt0;
        if (static_cast<std::uint16_t>(static_cast<unsigned>(crc_lo_) | (static_cast<unsigned>(byte) << 8U)) != crc_) {
          ++crc_errors_;
          return Result::kDropped;
        }
        ++frames_;
        return Result::kFrame;
    }
    return Result::kNeedMore;
  }

  /// Gives up a frame cut short (a byte lost on the line), so that the next frame is not read as its tail: the
  /// receiver calls it after a silence no frame has inside it (e.g. when an answer is overdue). True if a partial
  /// frame was dropped (counted in truncated()).
  bool abandon_partial() {
    if (state_ == State::kHunt0) return false;
    const bool partial = state_ != State::kHunt1;  // a lone sync byte is no frame yet
    state_ = State::kHunt0;
    if (partial) ++truncated_;
    return partial;
  }

  const Frame& frame() const { return frame_; }
  std::uint32_t frames() const { return frames_; }
  std::uint32_t truncated() const { return truncated_; }
  std::uint32_t crc_errors() const { return crc_errors_; }
  std::uint32_t length_errors() const { return length_errors_; }
  std::uint32_t errors() const { return crc_errors_ + length_errors_; }

 private:
  enum class State : std::uint8_t { kHunt0, kHunt1, kType, kSeq, kLength, kPayload, kCrcLo, kCrcHi };
  std::size_t max_payload_;
  State state_ = State::kHunt0;
  Frame frame_{};
  std::size_t received_ = 0;
  std::uint16_t crc_ = 0xFFFF;
  std::uint8_t crc_lo_ = 0;
  std::uint32_t frames_ = 0;
  std::uint32_t crc_errors_ = 0;
  std::uint32_t length_errors_ = 0;
  std::uint32_t truncated_ = 0;
};

}  // namespace lashid::hal::link

#include "server/streamed_answer.h"

#include <ostream>
#include <streambuf>
#include <utility>
#include <vector>

#include "server/request_io.h"

namespace penumbra::server {

namespace {

// Collects what is written into 64 KiB blocks and hands each to the sink (one chunk each):
// DataSink's own stream sends every `<<` as a chunk of its own.
class SinkBuffer : public std::streambuf {
 public:
  explicit SinkBuffer(httplib::DataSink& sink) : sink_(sink), block_(size_t(1) << 16) {
    setp(block_.data(), block_.data() + block_.size());
  }

 protected:
  int_type overflow(int_type c) override {
    if (!hand()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return hand() ? 0 : -1; }

 private:
  bool hand() {
    const size_t size = size_t(pptr() - pbase());
    if (size > 0 && !sink_.write(pbase(), size)) return false;
    setp(block_.data(), block_.data() + block_.size());
    return true;
  }

  httplib::DataSink& sink_;
  std::vector<char> block_;
};

}  // namespace

void sendStreamed(httplib::Response& res, const char* contentType, std::function<void(std::ostream&)> write) {
  res.status = 200;
  res.set_chunked_content_provider(
      contentType, guardedProvider([write = std::move(write)](size_t, httplib::DataSink& sink) {
        SinkBuffer buffer(sink);
        std::ostream out(&buffer);
        out.exceptions(std::ios::badbit);  // a client gone stops the writer at its next write
        write(out);
        out.flush();
        sink.done();
        return true;
      }));
}

}  // namespace penumbra::server

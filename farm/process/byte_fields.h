#pragma once
/// A flat byte layout for payloads that go between ranks (work orders, frames, encoded chunks):
/// fixed-size fields copied as they are (every rank runs the same build, so layout and
/// endianness agree), byte strings after their length. The reader refuses a payload that ends
/// early, a length or count that runs past its end, and bytes left over, naming the payload.
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace rf::farm {

struct ByteWriter {
    std::string out;
    template <class T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        out.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void bytes(const void* p, size_t n) {
        put(uint64_t(n));
        out.append(static_cast<const char*>(p), n);
    }
    void bytes(const std::string& s) { bytes(s.data(), s.size()); }
};

struct ByteReader {
    const std::string& in;
    const char* what;  ///< "chunk", "chunk order": the payload, for the error
    size_t at = 0;

    [[noreturn]] void bad(const char* why = "truncated") const {
        throw std::runtime_error(std::string("malformed ") + what + " message: " + why);
    }
    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        if (in.size() - at < sizeof(T)) bad();
        T v;
        std::memcpy(&v, in.data() + at, sizeof v);
        at += sizeof v;
        return v;
    }
    std::string bytes() {
        const uint64_t n = get<uint64_t>();
        if (n > in.size() - at) bad("a field runs past its end");
        std::string b = in.substr(at, size_t(n));
        at += size_t(n);
        return b;
    }
    /// A count of items of at least `least` bytes each: bounded by what is left, so a corrupt
    /// count cannot make the reader reserve gigabytes.
    uint32_t count(size_t least) {
        const uint32_t n = get<uint32_t>();
        if (uint64_t(n) * least > in.size() - at) bad("bad count");
        return n;
    }
    void end() const {
        if (at != in.size()) bad("bytes after its end");
    }
};

}  // namespace rf::farm

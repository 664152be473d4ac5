#pragma once
/// A set of frame indices held as sorted, disjoint, inclusive ranges: a film of 10⁹ frames is
/// one range of 8 bytes, never 10⁹ entries. Frame selections, the frames kept on disk and the
/// frames left to render are all of this kind. Header-only, so farm/output can use it without
/// linking anim/.
#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

namespace rf::anim {

struct FrameRange {
    int first = 0, last = 0;  ///< inclusive
    long long count() const { return 1LL + last - first; }
    bool operator==(const FrameRange& o) const { return first == o.first && last == o.last; }
};

/// Where a walk through a FrameRanges stands: the range, and the next frame in it.
struct FrameCursor {
    size_t range = 0;
    long long frame = 0;
};

class FrameRanges {
public:
    FrameRanges() = default;
    /// The frames listed, in any order (duplicates are one frame).
    FrameRanges(std::initializer_list<int> frames) {
        for (int f : frames) insert(f);
    }
    /// first..last inclusive; empty when last < first.
    static FrameRanges span(int first, int last) {
        FrameRanges r;
        if (first <= last) r.ranges_.push_back({first, last});
        return r;
    }

    /// Adds one frame: constant time when frames come in increasing order (how directories and
    /// selections are read), linear in the ranges otherwise.
    void insert(int f) {
        if (ranges_.empty() || f > ranges_.back().last) {
            if (!ranges_.empty() && 1LL + ranges_.back().last == f) ranges_.back().last = f;
            else ranges_.push_back({f, f});
            return;
        }
        auto it = std::lower_bound(ranges_.begin(), ranges_.end(), f, [](const FrameRange& r, int v) { return r.last < v; });
        if (it->first <= f) return;  // already held
        if (1LL + f == it->first) {
            it->first = f;
        } else {
            it = ranges_.insert(it, {f, f});
        }
        // Join with the range before it when they now touch.
        if (it != ranges_.begin() && 1LL + std::prev(it)->last == it->first) {
            std::prev(it)->last = it->last;
            ranges_.erase(it);
        }
    }

    /// Logarithmic in the number of ranges.
    bool contains(int f) const {
        auto it = std::lower_bound(ranges_.begin(), ranges_.end(), f, [](const FrameRange& r, int v) { return r.last < v; });
        return it != ranges_.end() && it->first <= f;
    }
    long long count() const {
        long long n = 0;
        for (const FrameRange& r : ranges_) n += r.count();
        return n;
    }
    bool empty() const { return ranges_.empty(); }
    const std::vector<FrameRange>& ranges() const { return ranges_; }

    /// These frames without those of `other`: linear in both range counts.
    FrameRanges minus(const FrameRanges& other) const {
        FrameRanges out;
        size_t j = 0;
        const std::vector<FrameRange>& o = other.ranges_;
        for (const FrameRange& r : ranges_) {
            long long from = r.first;
            while (j < o.size() && o[j].last < from) ++j;
            for (size_t k = j; k < o.size() && o[k].first <= r.last; ++k) {
                if (o[k].first > from) out.ranges_.push_back({int(from), o[k].first - 1});
                from = std::max(from, 1LL + o[k].last);
            }
            if (from <= r.last) out.ranges_.push_back({int(from), r.last});
        }
        return out;
    }
    /// The frames in both: linear in both range counts.
    FrameRanges intersect(const FrameRanges& other) const { return minus(minus(other)); }

    /// A cursor at the smallest frame.
    FrameCursor start() const { return {0, ranges_.empty() ? 0 : ranges_[0].first}; }
    bool atEnd(const FrameCursor& c) const { return c.range >= ranges_.size(); }
    /// The frame at the cursor (not at the end).
    int at(const FrameCursor& c) const { return int(c.frame); }
    /// Moves the cursor to the next frame in increasing order.
    void advance(FrameCursor& c) const {
        if (c.frame < ranges_[c.range].last) {
            ++c.frame;
        } else if (++c.range < ranges_.size()) {
            c.frame = ranges_[c.range].first;
        }
    }

    /// Every frame in increasing order, for range-for over small sets (it visits each frame).
    class const_iterator {
    public:
        using iterator_category = std::forward_iterator_tag;
        using value_type = int;
        using difference_type = std::ptrdiff_t;
        using pointer = const int*;
        using reference = int;
        const_iterator(const FrameRanges* r, FrameCursor c) : r_(r), c_(c) {}
        int operator*() const { return r_->at(c_); }
        const_iterator& operator++() {
            r_->advance(c_);
            return *this;
        }
        bool operator==(const const_iterator& o) const {
            const bool end = r_->atEnd(c_), oEnd = o.r_->atEnd(o.c_);
            return end || oEnd ? end == oEnd : c_.range == o.c_.range && c_.frame == o.c_.frame;
        }
        bool operator!=(const const_iterator& o) const { return !(*this == o); }

    private:
        const FrameRanges* r_;
        FrameCursor c_;
    };
    const_iterator begin() const { return {this, start()}; }
    const_iterator end() const { return {this, {ranges_.size(), 0}}; }

    bool operator==(const FrameRanges& o) const { return ranges_ == o.ranges_; }
    bool operator!=(const FrameRanges& o) const { return !(*this == o); }

    /// "0–9, 12" (an en dash inside a range), "none" when empty.
    std::string str() const {
        if (ranges_.empty()) return "none";
        std::string s;
        for (const FrameRange& r : ranges_) {
            if (!s.empty()) s += ", ";
            s += std::to_string(r.first);
            if (r.last != r.first) s += "–" + std::to_string(r.last);
        }
        return s;
    }
    friend std::ostream& operator<<(std::ostream& os, const FrameRanges& r) { return os << r.str(); }

private:
    std::vector<FrameRange> ranges_;
};

}  // namespace rf::anim

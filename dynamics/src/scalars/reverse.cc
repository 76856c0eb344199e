#include "tether/dynamics/scalars/reverse.h"

#include <algorithm>

namespace tether {
Tape::Tape() : previous_(internal::active_tape) {
  internal::active_tape = this;
  nodes_.swap(spare_nodes_);
  adjoints_.swap(spare_adjoints_);
  size_ = 0;
  adjoints_.clear();
}

Tape::~Tape() {
  internal::active_tape = previous_;
  if (nodes_.capacity() > spare_nodes_.capacity()) nodes_.swap(spare_nodes_);
  if (adjoints_.capacity() > spare_adjoints_.capacity()) adjoints_.swap(spare_adjoints_);
}

void Tape::Grow(int count) {
  const size_t needed = static_cast<size_t>(size_) + count;
  if (needed > nodes_.size()) nodes_.resize(std::max<size_t>({needed, 2 * nodes_.size(), 1024}));
}

Rev Tape::Variable(double value) { return Rev(value, Push(-1, 0.0, -1, 0.0)); }

int Tape::RecordExternal(int count, ExternalBackward backward) {
  const int first = size();
  Grow(count);
  std::fill_n(nodes_.begin() + first, count, Node{{-1, -1}, {0.0, 0.0}});
  size_ += count;
  externals_.push_back({first, count, std::move(backward)});
  return first;
}

void Tape::Backward(int mark) {
  adjoints_.resize(size_, 0.0);
  int i = size() - 1;
  while (i >= mark) {
    // the nodes down to the last output of the next external operation, or to the mark
    const int external_end = externals_.empty() ? -1 : externals_.back().first + externals_.back().count - 1;
    for (; i > external_end && i >= mark; --i) {
      const double adjoint = adjoints_[i];
      if (adjoint == 0.0) continue;
      const Node& node = nodes_[i];
      if (node.parent[0] >= 0) adjoints_[node.parent[0]] += node.partial[0] * adjoint;
      if (node.parent[1] >= 0) adjoints_[node.parent[1]] += node.partial[1] * adjoint;
    }
    if (i < mark) break;
    // an external operation's outputs are consecutive and have no parents: at the last one every use of them
    // has been swept, and its backward takes their adjoints on to its inputs
    External external = std::move(externals_.back());
    externals_.pop_back();
    external.backward(adjoints_.data() + external.first, this);
    i = external.first - 1;
  }
}

void Tape::Rewind(int mark) {
  size_ = mark;
  adjoints_.resize(std::min<size_t>(adjoints_.size(), mark));
  while (!externals_.empty() && externals_.back().first >= mark) externals_.pop_back();
}

}  // namespace tether

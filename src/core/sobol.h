// The first two dimensions of the Sobol sequence and hash-based Owen scrambling (Burley 2020,
// "Practical Hash-based Owen Scrambling"). Contract: every function is a pure, constexpr
// function of its arguments on 32-bit fixed point numbers (bit 31 = 1/2).
// - sobolPoint(i, 0) and sobolPoint(i, 1) form a (0,2)-sequence in base 2: every aligned block
//   of 2^k consecutive indices is a (0,k,2)-net (one point in each elementary interval of
//   area 2^-k).
// - nestedUniformScramble is a bijection in which bit j of the result (counted from the top)
//   depends only on bits 0..j of the input (from the top): it maps elementary intervals onto
//   elementary intervals, so nets stay nets; applied to an index it maps every aligned block of
//   2^k indices onto an aligned block of 2^k indices.
#pragma once
#include <array>
#include <bit>
#include <cstdint>

namespace rayes {

constexpr uint32_t reverseBits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}

// Columns of the second Sobol dimension's generator matrix (primitive polynomial x + 1): the
// Pascal triangle mod 2, column k holding binomial(k, j) mod 2 in bit 31 - j. The recurrence is
// Pascal's rule C(k, j) = C(k-1, j) + C(k-1, j-1); the first dimension's matrix is the identity.
constexpr std::array<uint32_t, 32> sobolPascalColumns() {
  std::array<uint32_t, 32> v{};
  v[0] = 1u << 31;
  for (int k = 1; k < 32; ++k) v[k] = v[k - 1] ^ (v[k - 1] >> 1);
  return v;
}
inline constexpr std::array<uint32_t, 32> kSobolPascalColumns = sobolPascalColumns();

// The product of the Pascal generator matrix with `index`, column by column (the definition).
constexpr uint32_t sobolPascalProduct(uint32_t index) {
  uint32_t x = 0;
  for (; index != 0; index &= index - 1) x ^= kSobolPascalColumns[std::countr_zero(index)];
  return x;
}

// Sobol point `index` in dimension 0 (van der Corput: the bit reversal) or 1, unscrambled.
// Dimension 1 is the same product in five steps instead of one per set bit: by Lucas's theorem
// C(k, j) is odd iff the bits of j are a subset of those of k, so output bit 31 - j is the XOR
// of the index bits k that are supersets of j: a superset-sum transform over the 5 bits of j.
constexpr uint32_t sobolPoint(uint32_t index, int dimension) {
  if (dimension == 0) return reverseBits(index);
  index ^= (index >> 1) & 0x55555555u;
  index ^= (index >> 2) & 0x33333333u;
  index ^= (index >> 4) & 0x0f0f0f0fu;
  index ^= (index >> 8) & 0x00ff00ffu;
  index ^= (index >> 16) & 0x0000ffffu;
  return reverseBits(index);
}

// Laine and Karras's permutation with Burley's constants: x + seed and x ^= x * even keep bit j
// a function of bits 0..j (from the bottom), so after bit reversal it is a nested scramble.
constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}

constexpr uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
  return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

}  // namespace rayes

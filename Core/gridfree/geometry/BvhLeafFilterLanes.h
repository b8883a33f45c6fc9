// The lane templates of the float leaf filter (BvhLeafFilter.h): the
// filter's bound, the float closest point it is taken from, and the two
// together, generic over the lane arithmetic L (LeafFilterSse,
// LeafFilterScalar, LeafFilterAvx2).
//
// Only BvhLeafFilter.h includes this file, inside its namespace, twice: once
// for the baseline and once within GCC target pragmas for AVX2, so that the
// eight-lane instantiations are AVX2 functions (a __m256 passed between
// functions of another instruction set would change their ABI). Hence no
// include guard and no includes of its own.

/// The filter's bound (see BvhLeafFilter.h) for lanes with d[i] = x - V_i (NV
/// vertices, ND coordinates) and any direction n: a float Low with
/// Low / |n| <= the distance from x to the primitive (the hull of the V_i,
/// taken as exact), or -1 where no positive bound is proved (NaN included).
/// (The lane templates take and give lanes by reference: with AVX2 lanes a
/// __m256 by value would be a different ABI outside AVX2 code.)
template <class L, int NV, int ND>
inline void LeafFilterLow(const typename L::F (&d)[NV][ND], const typename L::F (&n)[ND],
  const typename L::F& nn, typename L::F& result)
{
  using F = typename L::F;
  const F zero = L::Set(0.0f);
  // Below 2^-100 the squares may be subnormal and lose relative precision.
  F valid = L::Gt(nn, L::Set(0x1p-100f));
  F low = zero;
  for (int i = 0; i < NV; ++i)
  {
    F sum = L::Mul(n[0], d[i][0]);
    F mag = L::Abs(sum);
    for (int k = 1; k < ND; ++k)
    {
      const F p = L::Mul(n[k], d[i][k]);
      sum = L::Add(sum, p);
      mag = L::Add(mag, L::Abs(p));
    }
    const F li = L::Sub(L::Sub(sum, L::Mul(mag, L::Set(0x1p-20f))), L::Set(FLT_MIN));
    valid = L::And(valid, L::Gt(li, zero)); // false for NaN
    low = i == 0 ? li : L::Min(low, li);
  }
  result = L::Select(valid, low, L::Set(-1.0f));
}

/// Direction n = x - c for c the float closest point of each lane's
/// primitive (a segment if NV = 2, a triangle if NV = 3, in ND coordinates),
/// given d[i] = x - V_i.
template <class L, int NV, int ND>
inline void LeafFilterDirection(const typename L::F (&d)[NV][ND], typename L::F (&n)[ND])
{
  using F = typename L::F;
  const F zero = L::Set(0.0f);
  const F one = L::Set(1.0f);
  auto dot = [](const F* a, const F* b, F& s)
  {
    s = L::Mul(a[0], b[0]);
    for (int k = 1; k < ND; ++k)
    {
      s = L::Add(s, L::Mul(a[k], b[k]));
    }
  };
  F e1[ND];
  for (int k = 0; k < ND; ++k)
  {
    e1[k] = L::Sub(d[0][k], d[1][k]); // V1 - V0
  }
  static_assert(NV == 2 || NV == 3, "segments or triangles");
  if constexpr (NV == 2)
  {
    // Segment: the projection clamped to [0, 1]; a zero-length segment gives
    // NaN, which Max turns into 0.
    F along, length2;
    dot(d[0], e1, along);
    dot(e1, e1, length2);
    const F s = L::Min(L::Max(L::Div(along, length2), zero), one);
    for (int k = 0; k < ND; ++k)
    {
      n[k] = L::Sub(d[0][k], L::Mul(e1[k], s));
    }
  }
  else
  {
    F e2[ND];
    for (int k = 0; k < ND; ++k)
    {
      e2[k] = L::Sub(d[0][k], d[2][k]); // V2 - V0
    }
    // Ericson's regions (Real-Time Collision Detection, 5.1.5) without
    // branches: the closest point V0 + e1 s + e2 t of each region, selected
    // from the lowest priority to the highest.
    F d1, d2, d3, d4, d5, d6;
    dot(e1, d[0], d1);
    dot(e2, d[0], d2);
    dot(e1, d[1], d3);
    dot(e2, d[1], d4);
    dot(e1, d[2], d5);
    dot(e2, d[2], d6);
    const F va = L::Sub(L::Mul(d3, d6), L::Mul(d5, d4));
    const F vb = L::Sub(L::Mul(d5, d2), L::Mul(d1, d6));
    const F vc = L::Sub(L::Mul(d1, d4), L::Mul(d3, d2));
    const F inv = L::Div(one, L::Add(L::Add(va, vb), vc));
    F s = L::Mul(vb, inv); // inside the face
    F t = L::Mul(vc, inv);
    const F d43 = L::Sub(d4, d3), d56 = L::Sub(d5, d6);
    const F onBC = L::And(L::Le(va, zero), L::And(L::Le(zero, d43), L::Le(zero, d56)));
    const F tBC = L::Div(d43, L::Add(d43, d56));
    s = L::Select(onBC, L::Sub(one, tBC), s);
    t = L::Select(onBC, tBC, t);
    const F onAC = L::And(L::Le(vb, zero), L::And(L::Le(zero, d2), L::Le(d6, zero)));
    s = L::Select(onAC, zero, s);
    t = L::Select(onAC, L::Div(d2, L::Sub(d2, d6)), t);
    const F atC = L::And(L::Le(zero, d6), L::Le(d5, d6));
    s = L::Select(atC, zero, s);
    t = L::Select(atC, one, t);
    const F onAB = L::And(L::Le(vc, zero), L::And(L::Le(zero, d1), L::Le(d3, zero)));
    s = L::Select(onAB, L::Div(d1, L::Sub(d1, d3)), s);
    t = L::Select(onAB, zero, t);
    const F atB = L::And(L::Le(zero, d3), L::Le(d4, d3));
    s = L::Select(atB, one, s);
    t = L::Select(atB, zero, t);
    const F atA = L::And(L::Le(d1, zero), L::Le(d2, zero));
    s = L::Select(atA, zero, s);
    t = L::Select(atA, zero, t);
    for (int k = 0; k < ND; ++k)
    {
      n[k] = L::Sub(L::Sub(d[0][k], L::Mul(e1[k], s)), L::Mul(e2[k], t));
    }
  }
}

/// Low and |n|^2 of lanes with d[i] = x - V_i, n from LeafFilterDirection.
template <class L, int NV, int ND>
inline void LeafFilterLaneBounds(
  const typename L::F (&d)[NV][ND], typename L::F& low, typename L::F& nn)
{
  typename L::F n[ND];
  LeafFilterDirection<L, NV, ND>(d, n);
  nn = L::Mul(n[0], n[0]);
  for (int k = 1; k < ND; ++k)
  {
    nn = L::Add(nn, L::Mul(n[k], n[k]));
  }
  LeafFilterLow<L, NV, ND>(d, n, nn, low);
}


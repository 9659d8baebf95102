//! Noise bases (raw kernels): lattice value noise, Perlin's gradient noise and Olano's mNoise,
//! with their fades and analytic gradients.

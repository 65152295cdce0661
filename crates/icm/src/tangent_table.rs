//! Eq. (6), E_t(S) = dφ/dε at ε = φ⁻¹(S), tabulated on the compressive
//! branch so the ICM can call it at every plane.
//!
//! Why: the ICM evaluates E_t at two stresses per plane (Heun), 200 000
//! times for 100 000 planes. Inverting φ through the generic model costs
//! some 10 µs (a bracketed Newton from ε = 0), far over the 0.1 s budget.
//! So φ and E_t are evaluated once on strains uniform in ln λ (λ = 1 + ε)
//! from the end of φ's monotonic range up to ε = 0 exactly, and E_t is
//! interpolated in S with cubic Hermite polynomials whose end slopes are
//! dE_t/dS = (dE_t/dε) / E_t (the chain rule, since dS/dε = E_t). The
//! interpolation error is below 1e-9 relative (tested against the exact
//! law); stresses outside the table fall back to the exact inversion, which
//! also produces the material's own out-of-range error.

use hypercontact_material::ContactLaw;

/// Nodes of the table: 2^13 intervals.
const NODES: usize = 8193;

/// E_t against S on the compressive branch, S increasing up to φ(0) ≈ 0.
#[derive(Clone, Debug)]
pub struct TangentTable {
    stress_pa: Vec<f64>,
    tangent_pa: Vec<f64>,
    /// dE_t/dS at each node.
    slope: Vec<f64>,
}

impl TangentTable {
    pub fn new(law: &ContactLaw) -> Self {
        let ln_stretch_min = (1.0 + law.range().eps_min).ln();
        let (mut stress_pa, mut tangent_pa, mut slope) = (
            Vec::with_capacity(NODES),
            Vec::with_capacity(NODES),
            Vec::with_capacity(NODES),
        );
        for i in 0..NODES {
            // i = NODES − 1 gives ln λ = 0, so ε = 0 exactly.
            let eps = (ln_stretch_min * (NODES - 1 - i) as f64 / (NODES - 1) as f64).exp() - 1.0;
            let e_t = law.tangent_modulus_pa(eps);
            // dE_t/dε by a central difference scaled to λ, error ~ 1e-12.
            let step = 1e-6 * (1.0 + eps);
            let de_deps = (law.tangent_modulus_pa(eps + step) - law.tangent_modulus_pa(eps - step))
                / (2.0 * step);
            stress_pa.push(law.phi_pa(eps));
            tangent_pa.push(e_t);
            slope.push(de_deps / e_t);
        }
        Self {
            stress_pa,
            tangent_pa,
            slope,
        }
    }

    /// E_t at stress S, Pa; None outside the tabulated stresses.
    pub fn get(&self, stress_pa: f64) -> Option<f64> {
        let s = &self.stress_pa;
        if !(stress_pa >= s[0] && stress_pa <= s[s.len() - 1]) {
            return None;
        }
        // The interval [s[k], s[k + 1]] holding the stress.
        let k = s.partition_point(|&x| x <= stress_pa).clamp(1, s.len() - 1) - 1;
        let h = s[k + 1] - s[k];
        let t = (stress_pa - s[k]) / h;
        let (t2, t3) = (t * t, t * t * t);
        Some(
            (2.0 * t3 - 3.0 * t2 + 1.0) * self.tangent_pa[k]
                + (t3 - 2.0 * t2 + t) * h * self.slope[k]
                + (3.0 * t2 - 2.0 * t3) * self.tangent_pa[k + 1]
                + (t3 - t2) * h * self.slope[k + 1],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use hypercontact_material::presets::paper_epdm;
    use std::sync::Arc;

    /// The largest relative error of the table against the exact law at
    /// strains off the nodes, from the end of the range to just below 0.
    fn worst_table_error(law: &ContactLaw, table: &TangentTable) -> f64 {
        let eps_min = law.range().eps_min;
        let mut worst: f64 = 0.0;
        for k in 1..2000 {
            let eps = eps_min * (1.0 - (k as f64 + 0.37) / 2001.0);
            let exact = law.tangent_modulus_pa(eps);
            let Some(tabulated) = table.get(law.phi_pa(eps)) else {
                panic!("ε = {eps} not tabulated")
            };
            worst = worst.max((tabulated / exact - 1.0).abs());
        }
        worst
    }

    #[test]
    fn table_matches_the_exact_law_across_the_compressive_branch() {
        let law = ContactLaw::new(Arc::new(paper_epdm())).unwrap();
        let table = TangentTable::new(&law);
        let worst = worst_table_error(&law, &table);
        assert!(worst < 1e-9, "worst relative error {worst:.3e}");
        // The node at ε = 0 reproduces E_t(0) = 6 μ0.
        let e0 = law.tangent_modulus_pa(0.0);
        let at_zero = table.get(law.phi_pa(0.0)).unwrap();
        assert!((at_zero / e0 - 1.0).abs() < 1e-12);
        assert!(table.get(law.range().stress_min_pa * 1.01).is_none());
        assert!(table.get(1.0e3).is_none(), "tension is not tabulated");
    }

    #[test]
    fn a_uniaxial_table_matches_its_own_law() {
        let model = Arc::new(paper_epdm());
        let law = ContactLaw::in_mode(model, hypercontact_material::Mode::Uniaxial).unwrap();
        let table = TangentTable::new(&law);
        let worst = worst_table_error(&law, &table);
        assert!(worst < 1e-9, "worst relative error {worst:.3e}");
        // E_t(0) = E0 = 3 μ0 for the uniaxial curve.
        use hypercontact_material::Hyperelastic;
        let e0 = 3.0 * paper_epdm().shear_modulus_pa();
        let at_zero = table.get(law.phi_pa(0.0)).unwrap();
        assert!((at_zero / e0 - 1.0).abs() < 1e-9, "{at_zero} vs {e0}");
    }
}

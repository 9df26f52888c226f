-- Family 12: case-generate (VHDL-2008) choosing a source model by a static selector; an alternative declares its
-- own terminal and quantities (named case_src__inner, case_src__vri, ... in the netlist).
-- kind = 2 selects the alternative `when lossy: 2 | 3`: a 10 V step source with r_int = 4 kOhm driving
-- r_load = 4 kOhm with c = 0.5 uF: k = 1/2, tau = (4 kOhm || 4 kOhm)*c = 1 ms,
--   vl(t) = 5*(1 - exp(-t/1 ms)),  the internal resistor's current iri(t) = (u - vl(t))/r_int (t > 0).
-- (kind = 1 would give vl = 10 V at once; any other kind, the others alternative, vl = 0.)
library ieee;
use ieee.electrical_systems.all;

entity case_gen_tb is
  generic (kind : integer := 2; u : voltage := 10.0; r_int : resistance := 4.0e3;
           r_load : resistance := 4.0e3; c : capacitance := 0.5e-6);
end entity case_gen_tb;

architecture behav of case_gen_tb is
  terminal load : electrical;
  quantity vl across il through load to electrical_ref;
  quantity vcap across icap through load to electrical_ref;
begin
  vl == r_load * il;
  icap == c * vcap'dot;

  case_src : case kind generate
    when ideal: 1 =>
      quantity vs across isrc through load to electrical_ref;
    begin
      if domain = quiescent_domain use
        vs == 0.0;
      else
        vs == u;
      end use;
    end ideal;
    when lossy: 2 | 3 =>
      terminal inner : electrical;
      quantity vs across isrc through inner to electrical_ref;
      quantity vri across iri through inner to load;
    begin
      if domain = quiescent_domain use
        vs == 0.0;
      else
        vs == u;
      end use;
      vri == r_int * iri;
    when others =>
      quantity vs across isrc through load to electrical_ref;
    begin
      isrc == 0.0;
  end generate case_src;
end architecture behav;

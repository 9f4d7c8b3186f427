//! Plain-text tables for terminal output.

/// `lines` as columns two spaces apart, each as wide as its widest cell; text columns left
/// aligned, those `right_aligned` says are numbers right aligned.
pub fn align_columns<const N: usize>(
    lines: &[[String; N]],
    right_aligned: impl Fn(usize) -> bool,
) -> String {
    let widths: Vec<usize> = (0..N)
        .map(|column| {
            lines
                .iter()
                .map(|line| line[column].chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut table = String::new();
    for line in lines {
        let cells: Vec<String> = line
            .iter()
            .zip(&widths)
            .enumerate()
            .map(|(column, (cell, &width))| {
                let pad = " ".repeat(width.saturating_sub(cell.chars().count()));
                if right_aligned(column) {
                    format!("{pad}{cell}")
                } else {
                    format!("{cell}{pad}")
                }
            })
            .collect();
        table.push_str(cells.join("  ").trim_end());
        table.push('\n');
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_take_the_widest_cell_and_numbers_align_right() {
        let lines =
            [["name", "n"], ["mapper", "12"], ["x", "3"]].map(|line| line.map(str::to_owned));
        let table = align_columns(&lines, |column| column == 1);
        assert_eq!(table, "name     n\nmapper  12\nx        3\n");
    }
}
